"""The kernel's sleeve in FreeCAD: the BREP text of stkernel.sleeve_brep becomes a valid Part solid
with the sleeve's volume, placed where the case file says, and FreeCAD's mesh of it matches ours."""
import json
import math
import os
import subprocess
import sys

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
ST_PYTHON = os.environ.get("ST_PYTHON_DIR", os.path.join(os.getcwd(), "python"))


def stkernel_has_occt():
    sys.path.insert(0, ST_PYTHON)
    try:
        import stkernel
    except ImportError:
        return False
    return stkernel.has_occt


@pytest.mark.skipif(not os.path.exists(FREECAD_LIB), reason="FreeCAD is not installed")
@pytest.mark.skipif(not stkernel_has_occt(), reason="stkernel was built without OpenCASCADE (ST_WITH_OCCT)")
def test_sleeve_brep_is_a_valid_solid_in_freecad(tmp_path):
    entry, direction = (12.5, -40.0, 7.25), (1.0, 2.0, -3.0)
    r, R, L, offset = 2.0, 3.0, 20.0, 1.5
    script = tmp_path / "run.py"
    script.write_text(f"""
import json, sys
sys.path.append({FREECAD_LIB!r})
import FreeCAD, Part, MeshPart
sys.path.insert(0, {ST_PYTHON!r})
import stkernel
text = stkernel.sleeve_brep({entry!r}, {direction!r}, {r!r}, {R!r}, {L!r}, {offset!r}, name="pedicle-left")
s = Part.Shape()
s.importBrepFromString(text, False)
m = MeshPart.meshFromShape(Shape=s, LinearDeflection=0.01, AngularDeflection=0.5, Relative=False)
c = s.Solids[0].CenterOfMass if s.Solids else None
print("RESULT", json.dumps(dict(type=s.ShapeType, valid=s.isValid(), closed=s.isClosed(), solids=len(s.Solids),
      faces=len(s.Faces), volume=s.Volume, centre=[c.x, c.y, c.z] if c else None,
      mesh_solid=m.isSolid(), mesh_nonmanifold=m.hasNonManifolds(), mesh_volume=m.Volume)))
""")
    env = dict(os.environ, FREECAD_USER_HOME=str(tmp_path), FREECAD_USER_DATA=str(tmp_path))
    p = subprocess.run(["/usr/bin/python3", str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    result = json.loads([l for l in p.stdout.splitlines() if l.startswith("RESULT")][0][len("RESULT"):])

    assert result["type"] == "Solid"
    assert result["valid"] and result["closed"]
    assert result["solids"] == 1 and result["faces"] == 4
    exact = math.pi * (R * R - r * r) * L
    assert abs(result["volume"] - exact) < 1e-9 * exact
    # The centre of mass is on the axis, half-way up the sleeve (z measured against the direction).
    n = math.sqrt(sum(x * x for x in direction))
    mid = offset + L / 2
    expected_centre = [e - mid * x / n for e, x in zip(entry, direction)]
    assert max(abs(a - b) for a, b in zip(result["centre"], expected_centre)) < 1e-9

    # FreeCAD meshes it into a closed solid, with a volume as close as our own tessellation's.
    assert result["mesh_solid"] and not result["mesh_nonmanifold"]
    sys.path.insert(0, ST_PYTHON)
    import stkernel

    v, f = stkernel.tessellate_sleeve(entry, direction, r, R, L, offset, linear_deflection=0.01)
    ours = stkernel.check_solid(v, f)["volume"]
    # Both within the chordal error of 0.01 mm: outer wall loses, inner wall gains at most this.
    bound = math.pi * L * 0.01 * 2 * R
    assert abs(result["mesh_volume"] - exact) < bound
    assert abs(ours - exact) < bound

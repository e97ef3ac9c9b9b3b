"""The kernel inside FreeCAD: the design macro builds Mesh features of a valid, closed template."""
import os
import subprocess
import sys

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


@pytest.mark.skipif(not os.path.exists(FREECAD_LIB), reason="FreeCAD is not installed")
def test_macro_designs_template_in_a_freecad_document(tmp_path):
    fcstd = tmp_path / "vertebra.FCStd"
    script = tmp_path / "run.py"
    script.write_text(f"""
import sys
sys.path.append({FREECAD_LIB!r})
import FreeCAD, Mesh
sys.path.insert(0, {os.path.join(ROOT, 'examples', 'macros')!r})
import design_in_freecad as d
doc, tpl, r = d.design({os.path.join(ROOT, 'examples', 'cases', 'vertebra-pedicle.json')!r}, {str(fcstd)!r})
m = tpl.Mesh
m.write({str(tmp_path / "from_freecad.stl")!r})
print("RESULT", m.CountFacets, m.isSolid(), m.hasNonManifolds(), round(m.Volume, 1))
""")
    env = dict(os.environ, FREECAD_USER_HOME=str(tmp_path), FREECAD_USER_DATA=str(tmp_path),
               ST_PYTHON=os.environ.get("ST_PYTHON_DIR", os.path.join(os.getcwd(), "python")))
    p = subprocess.run(["/usr/bin/python3", str(script)], capture_output=True, text=True, env=env, timeout=300)
    assert p.returncode == 0, p.stderr
    line = [l for l in p.stdout.splitlines() if l.startswith("RESULT")][0].split()
    facets, solid, nonmanifold, volume = int(line[1]), line[2], line[3], float(line[4])
    assert facets > 1000
    assert solid == "True" and nonmanifold == "False"
    assert volume > 1000
    assert fcstd.exists() and fcstd.stat().st_size > 10000
    # The mesh as FreeCAD holds and exports it (float32) is still a valid solid for the exact check.
    sys.path.insert(0, env["ST_PYTHON"])
    import stkernel

    report = stkernel.check_solid(*stkernel.read_mesh(str(tmp_path / "from_freecad.stl")))
    assert report["valid"], report["summary"]
    assert abs(report["volume"] - volume) < 0.01 * volume

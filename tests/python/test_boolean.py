"""Boolean operations and drilling tubes through the module and the tool."""
import json
import os
import subprocess

import numpy as np
import pytest

from conftest import EXAMPLES, TOOL, icosphere

CASES = os.path.join(EXAMPLES, "cases")


def volume(v, f):
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    return float(np.einsum("ij,ij->i", a, np.cross(b, c)).sum() / 6.0)


def test_volumes_of_union_difference_intersection_agree(stk):
    va, fa = icosphere(10.0, 3)
    vb, fb = icosphere(6.0, 3)
    vb = vb + np.array([8.0, 1.0, -0.5])
    res = {op: stk.mesh_boolean(va, fa, vb, fb, op) for op in ("union", "difference", "intersection")}
    for op, r in res.items():
        report = stk.check_solid(*r["mesh"])
        assert report["valid"], (op, report)
    vu, vd, vi = (volume(*res[op]["mesh"]) for op in ("union", "difference", "intersection"))
    assert vi > 0.05 * volume(vb, fb)
    assert vu + vi == pytest.approx(volume(va, fa) + volume(vb, fb), rel=1e-5)
    assert vd == pytest.approx(volume(va, fa) - vi, rel=1e-5)
    assert res["union"]["from_b"].shape == (len(res["union"]["mesh"][1]),)


def test_bad_operands_raise_value_error(stk):
    va, fa = icosphere(5.0, 2)
    with pytest.raises(ValueError, match="second operand"):
        stk.mesh_boolean(va, fa, va, fa[:-1], "union")
    with pytest.raises(ValueError, match="op"):
        stk.mesh_boolean(va, fa, va, fa, "xor")


def test_design_template_with_tubes(stk):
    case = stk.read_case(os.path.join(CASES, "sacrum-iliosacral.json"))
    v, f = stk.read_mesh(case["bone"])
    r = stk.design_template(v, f, case["boundary_points"], case["thickness"], case["clearance"],
                            inside=case["inside"], sampling_step=case["sampling_step"], tubes=case["tubes"])
    assert r["solid"]["valid"] and r["solid"]["components"] == 1
    assert r["times"]["boolean_operation"] > 0
    assert len(r["tubes"]) == 1 and r["tubes"][0]["name"] == "IS1"
    assert r["from_tube"].sum() > 50
    # The body plus the sleeve: more volume than the body alone, less than body plus the whole column.
    body = volume(*r["body"])
    assert volume(*r["shell"]) > body
    # add_tubes on the body gives the same guide.
    g = stk.add_tubes(*r["body"], r["inner_faces"], v, f, case["tubes"])
    assert volume(*g["mesh"]) == pytest.approx(volume(*r["shell"]), rel=1e-9)


def test_tube_errors_name_the_tube(stk):
    case = stk.read_case(os.path.join(CASES, "sacrum-iliosacral.json"))
    v, f = stk.read_mesh(case["bone"])
    r = stk.design_template(v, f, case["boundary_points"], case["thickness"], inside=case["inside"],
                            sampling_step=case["sampling_step"])
    far = dict(case["tubes"][0], name="far", entry=np.array(case["tubes"][0]["entry"]) + 80.0)
    with pytest.raises(RuntimeError, match="'far' misses the template"):
        stk.add_tubes(*r["body"], r["inner_faces"], v, f, [far])
    with pytest.raises(ValueError, match="outer_radius"):
        stk.add_tubes(*r["body"], r["inner_faces"], v, f, [dict(case["tubes"][0], outer_radius=0.5)])
    with pytest.raises(ValueError, match=r"tubes\[0\]: missing 'length'"):
        stk.add_tubes(*r["body"], r["inner_faces"], v, f, [{"entry": [0, 0, 0], "direction": [0, 0, 1],
                                                             "inner_radius": 1, "outer_radius": 2}])


def run(*args):
    return subprocess.run([TOOL, *args], capture_output=True, text=True, timeout=600)


def test_tool_designs_guides_with_tubes_and_reports_the_boolean_row(tmp_path):
    out, rep, ops = tmp_path / "g.stl", tmp_path / "r.json", tmp_path / "ops"
    p = run("design", os.path.join(CASES, "maxilla-implants.json"), "-o", str(out), "--report", str(rep),
            "--operands", str(ops))
    assert p.returncode == 0, p.stderr
    report = json.loads(rep.read_text())
    assert report["solid"]["valid"] and report["solid"]["components"] == 1
    assert report["times"]["boolean_operation"] > 0
    assert [t["name"] for t in report["tubes"]] == ["16", "13", "11", "23", "26"]
    # The same guide again with the tool's Boolean subcommands on the written operands.
    united, guide = tmp_path / "u.stl", tmp_path / "d.stl"
    assert run("union", str(ops / "body.stl"), str(ops / "columns.stl"), "-o", str(united)).returncode == 0
    d = run("difference", str(united), str(ops / "bores.stl"), "-o", str(guide))
    assert d.returncode == 0, d.stderr
    assert run("check", str(guide)).returncode == 0


def test_tool_boolean_refuses_open_operands_without_output(tmp_path):
    open_mesh = tmp_path / "open.stl"
    # One triangle: open.
    open_mesh.write_text("solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 1 0 0\nvertex 0 1 0\n"
                         "endloop\nendfacet\nendsolid t\n")
    out = tmp_path / "u.stl"
    p = run("union", str(open_mesh), str(open_mesh), "-o", str(out))
    assert p.returncode == 2
    assert "open.stl" in p.stderr and "closed" in p.stderr
    assert not out.exists()
    p = run("union", str(open_mesh), "-o", str(out))
    assert p.returncode == 2 and "two meshes" in p.stderr

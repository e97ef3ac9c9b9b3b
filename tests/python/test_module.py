"""The stkernel module: numpy in and out, clear errors, same operations as the C++ API."""
import math
import os

import numpy as np
import pytest

from conftest import EXAMPLES, icosphere


def circle(r, polar, n):
    a = 0.1 + 2 * math.pi * np.arange(n) / n
    return np.stack([r * math.sin(polar) * np.cos(a), r * math.sin(polar) * np.sin(a),
                     np.full(n, r * math.cos(polar))], axis=1)


def test_cut_sphere_cap_area(stk):
    V, F = icosphere(10.0, 5)
    cv, cf, rim = stk.cut_region(V, F, circle(10.0, math.pi / 3, 12))
    a = np.cross(cv[cf[:, 1]] - cv[cf[:, 0]], cv[cf[:, 2]] - cv[cf[:, 0]])
    area = 0.5 * np.linalg.norm(a, axis=1).sum()
    expected = 2 * math.pi * 100 * (1 - math.cos(math.pi / 3))
    assert abs(area - expected) < 0.01 * expected
    assert len(rim) > 50
    assert np.allclose(cv[rim][:, 2], 10 * math.cos(math.pi / 3), atol=0.2)


def test_design_template_on_sphere_is_valid(stk):
    V, F = icosphere(20.0, 5)
    r = stk.design_template(V, F, circle(20.0, 0.7, 9), thickness=2.5, resolution=0.25)
    assert r["solid"]["valid"], r["solid"]["summary"]
    assert r["solid"]["components"] == 1
    assert 2.25 < r["fit"]["outer_to_inner"]["min"] and r["fit"]["outer_to_inner"]["max"] < 2.75
    sv, sf = r["shell"]
    assert sv.shape[1] == 3 and sf.shape[1] == 3
    # The module's own check agrees.
    assert stk.check_solid(sv, sf)["valid"]


def test_insertion_analysis_of_a_cap_beyond_the_equator(stk):
    # A cap of polar angle 110 degrees around +z: along -z the band beyond the equator (area
    # 2 pi R^2 cos(70 deg)) is hidden; 'auto' finds a direction with no more than that.
    V, F = icosphere(20.0, 5)
    ring = circle(20.0, math.radians(110), 16)
    band = 2 * math.pi * 400 * math.cos(math.radians(70))
    down = stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], insertion=[0, 0, -3], check=False)
    ins = down["insertion"]
    assert not ins["auto"] and np.allclose(ins["direction"], [0, 0, -1])
    assert abs(ins["undercut_area_mm2"] - band) < 0.05 * band
    assert ins["hidden"].shape == (len(ins["region"][1]),)
    # Blocked out (the default with an insertion), the band under the equator reaches the rim: it is
    # cut off, and a skirt hangs from the equator straight down to the drawn border (z = 20 cos 110),
    # a cylinder of the band's own area (Archimedes); the guide comes off upwards.
    assert ins["blocked_out"] and ins["trimmed_zones"] >= 1
    assert abs(ins["trimmed_area_mm2"] - band) < 0.1 * band
    depth = -20 * math.cos(math.radians(110))
    assert abs(ins["skirt_depth_mm"] - depth) < 0.05
    assert abs(ins["skirt_area_mm2"] - band) < 0.03 * band
    checked = stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], insertion=[0, 0, -1])
    assert checked["solid"]["valid"] and checked["insertion"]["removable"]
    sv, _ = checked["shell"]
    assert abs(sv[:, 2].min() + depth) < 0.05
    kept = stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], insertion=[0, 0, -1], block_out=False)
    assert not kept["insertion"]["removable"] and len(kept["insertion"]["blocking"]) > 0
    auto = stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], insertion="auto", check=False)
    assert auto["insertion"]["auto"]
    assert auto["insertion"]["undercut_area_mm2"] <= ins["undercut_area_mm2"] + 0.01 * band  # sampling
    with pytest.raises(ValueError, match="insertion"):
        stk.design_template(V, F, ring, thickness=2.0, insertion="up")
    assert "insertion" not in stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], check=False)


def test_a_guide_on_a_ball_turns_about_its_centre(stk):
    # The cap's guide (80 degrees) seats on a tessellated sphere: turns about the centre are held only
    # by the facets (the bone's vertex normals are not exactly radial), so the score is nearly 0 and
    # the worst motion is a turn about an axis through the centre.
    V, F = icosphere(20.0, 5)
    ring = circle(20.0, math.radians(80), 16)
    r = stk.design_template(V, F, ring, thickness=2.0, inside=[0, 0, 20], insertion=[0, 0, -1])
    s = r["stability"]
    assert s["lift_off_free"] and 0.0 <= s["score"] < 0.01
    worst = s["worst_motion"]
    assert worst["kind"] == "turn" and worst["lift"] < 0.01
    assert np.linalg.norm(np.cross(np.asarray(worst["point"]), worst["direction"])) < 2.0  # near the centre
    assert s["contact_points"].shape == (s["contacts"], 3)
    assert s["contacts"] > 0.9 * 2 * math.pi * 400 * (1 - math.cos(math.radians(80)))
    assert abs(np.linalg.norm(s["contact_points"], axis=1) - 20.0).max() < 0.1
    assert r["times"]["stability"] > 0
    # The same analysis of the guide's inner surface alone: the module's function for any guide.
    inner_v, inner_f = r["inner"]
    again = stk.analyse_stability(inner_v, inner_f, V, F, [0, 0, -1], reach=0.05, outer_points=r["outer"][0])
    assert abs(again["score"] - s["score"]) < 0.005 and again["worst_motion"]["kind"] == "turn"
    assert again["press_point"] in r["outer"][0].tolist()
    # The shell's own inner facets face the bone: said so, they give the same contacts.
    sv, sf = r["shell"]
    shell = stk.analyse_stability(sv, sf[:r["inner_faces"]], V, F, [0, 0, -1], reach=0.05, toward_bone=True)
    assert shell["contacts"] == again["contacts"] and shell["lift_off_free"]
    with pytest.raises(ValueError, match="direction"):
        stk.analyse_stability(inner_v, inner_f, V, F, None)


def test_offset_and_ruled_surface(stk):
    V, F = icosphere(10.0, 3)
    ov, of = stk.offset_surface(V, F, 1.0, 0.2, False)
    d = np.linalg.norm(ov, axis=1)
    # The unsigned offset of a closed sphere has two sheets, at radius 9 and 11.
    assert np.abs(np.abs(d - 10.0) - 1.0).max() < 0.1
    assert (d > 10).any() and (d < 10).any()
    p = circle(10, math.pi / 2, 30)
    q = circle(12, math.pi / 2, 45)
    tris = stk.ruled_surface(p, q)
    assert tris.shape == (75, 3)


def test_bad_input_raises_value_error(stk):
    V, F = icosphere(10.0, 2)
    with pytest.raises(ValueError, match="at least 3"):
        stk.design_template(V, F, circle(10, 1.0, 2), thickness=2.0)
    with pytest.raises(ValueError, match="thickness"):
        stk.design_template(V, F, circle(10, 1.0, 8), thickness=-1.0)
    with pytest.raises(ValueError, match=r"\(n, 3\)"):
        stk.design_template(V[:, :2], F, circle(10, 1.0, 8), thickness=2.0)
    bad = F.copy()
    bad[0, 0] = 10 ** 6
    with pytest.raises(ValueError, match="refers to vertex"):
        stk.check_solid(V, bad)
    Vn = V.copy()
    Vn[3, 1] = np.nan
    with pytest.raises(ValueError, match="non-finite"):
        stk.check_solid(Vn, F)


def test_geometry_failure_raises_runtime_error(stk):
    # A loop around a torus tube does not separate the surface.
    nu, nv, R, r = 48, 24, 10.0, 3.0
    u, v = np.meshgrid(2 * np.pi * np.arange(nu) / nu, 2 * np.pi * np.arange(nv) / nv, indexing="ij")
    V = np.stack([(R + r * np.cos(v)) * np.cos(u), (R + r * np.cos(v)) * np.sin(u), r * np.sin(v)], -1).reshape(-1, 3)
    idx = lambda i, j: (i % nu) * nv + (j % nv)
    F = []
    for i in range(nu):
        for j in range(nv):
            F += [(idx(i, j), idx(i + 1, j), idx(i + 1, j + 1)), (idx(i, j), idx(i + 1, j + 1), idx(i, j + 1))]
    F = np.array(F)
    vv = 0.05 + 2 * np.pi * np.arange(8) / 8
    pts = np.stack([(R + r * np.cos(vv)) * math.cos(0.13), (R + r * np.cos(vv)) * math.sin(0.13), r * np.sin(vv)], -1)
    with pytest.raises(RuntimeError, match="does not separate"):
        stk.cut_region(V, F, pts)


def test_read_mesh_and_case(stk, outdir):
    case = stk.read_case(os.path.join(EXAMPLES, "cases", "vertebra-pedicle.json"))
    assert case["thickness"] == 2.5
    V, F = stk.read_mesh(case["bone"])
    assert F.shape == (130956, 3)
    path = str(outdir / "copy.stl")
    stk.write_stl(V, F, path)
    V2, F2 = stk.read_mesh(path)
    assert F2.shape == F.shape
    assert np.abs(np.sort(V2, axis=0) - np.sort(V, axis=0)).max() < 1e-4

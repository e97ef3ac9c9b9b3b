"""Case files and plans through the module: the kernel's write_case, apply_plan and preset lookup, the
ones the workbench calls."""
import os

import numpy as np
import pytest

from conftest import EXAMPLES

CASES = os.path.join(EXAMPLES, "cases")
PLANS = os.path.join(EXAMPLES, "plans")


def test_written_case_reads_back_the_same(stk, tmp_path):
    case = stk.read_case(os.path.join(CASES, "maxilla-implants.json"))
    path = tmp_path / "sub" / "case.json"
    path.parent.mkdir()
    stk.write_case(case, str(path))
    again = stk.read_case(str(path))
    assert os.path.samefile(again["bone"], case["bone"])
    assert np.array_equal(again["boundary_points"], case["boundary_points"])
    assert [t["name"] for t in again["tubes"]] == [t["name"] for t in case["tubes"]]
    assert again["thickness"] == case["thickness"] and again["clearance"] == case["clearance"]


def test_invalid_case_is_refused_and_not_written(stk, tmp_path):
    case = stk.read_case(os.path.join(CASES, "maxilla-implants.json"))
    case["tubes"][0]["outer_radius"] = 0.1  # inside the bore
    with pytest.raises(ValueError, match=r"tubes\[0\]\.outer_radius"):
        stk.write_case(case, str(tmp_path / "case.json"))
    assert not os.listdir(tmp_path)


def test_plan_applied_to_a_case(stk):
    case = stk.read_case(os.path.join(CASES, "maxilla-implants.json"))
    drill = stk.find_sleeve_preset(stk.sleeve_presets(), "DRILL-2.5")  # case ignored
    assert drill["name"] == "drill-2.5"
    new, warnings = stk.apply_plan(case, os.path.join(PLANS, "maxilla-implants.csv"), "LPS", drill)
    assert len(new["tubes"]) == 5 and np.array_equal(new["boundary_points"], case["boundary_points"])
    added, _ = stk.apply_plan(case, os.path.join(PLANS, "maxilla-implants.csv"), "LPS", drill, add_tubes=True)
    assert len(added["tubes"]) == len(case["tubes"]) + 5
    with pytest.raises(ValueError, match="no sleeve preset"):
        stk.find_sleeve_preset(stk.sleeve_presets(), "no-such-sleeve")


def test_slots_read_written_and_designed_through_the_module(stk, tmp_path):
    """The tibia example's two saw slots survive the workbench's read and write, and design_template
    cuts them: each as wide as blade + 2 x clearance, its blade path free, the guide one valid solid."""
    case = stk.read_case(os.path.join(CASES, "tibia-osteotomy.json"))
    assert [s["name"] for s in case["slots"]] == ["proximal cut", "distal cut"]
    path = tmp_path / "case.json"
    stk.write_case(case, str(path))
    again = stk.read_case(str(path))
    for a, b in zip(case["slots"], again["slots"]):
        assert a["name"] == b["name"] and a["closed"] == b["closed"]
        assert np.allclose(a["normal"], b["normal"]) and a["blade"] == b["blade"]
    bad = dict(case["slots"][0], blade=0.0)
    with pytest.raises(ValueError, match=r"slots\[0\]\.blade"):
        stk.write_case(dict(case, slots=[bad]), str(tmp_path / "bad.json"))
    v, f = stk.read_mesh(case["bone"])
    r = stk.design_template(v, f, case["boundary_points"], case["thickness"], clearance=case["clearance"],
                            inside=case["inside"], slots=case["slots"])
    assert r["solid"]["valid"], r["solid"]["summary"]
    assert [s["name"] for s in r["slots"]] == ["proximal cut", "distal cut"]
    for s, planned in zip(r["slots"], case["slots"]):
        assert s["blade_path_free"]
        assert s["width"] == pytest.approx(planned["blade"] + 2 * planned["clearance"])
    # The workbench's way: the slots added to the designed body (add_tubes) give the same guide.
    g = stk.add_tubes(*r["body"], r["inner_faces"], v, f, [], clearance=case["clearance"], slots=case["slots"])
    assert [s["name"] for s in g["slots"]] == ["proximal cut", "distal cut"]
    assert all(s["blade_path_free"] for s in g["slots"]), "add_tubes checks the blade paths too"
    assert stk.check_solid(*g["mesh"])["volume"] == pytest.approx(r["solid"]["volume"], rel=1e-9)


def test_labels_read_written_and_engraved_through_the_module(stk, tmp_path):
    """The tibia example's label survives read and write, and design_template engraves it: 'labels' in
    the result with the planned depth, the wall left under it at least thickness - depth (5 %), 1 mm clear
    of the sleeves and slots; a bad label is refused naming it and the key."""
    if not stk.has_occt:
        pytest.skip("labels need OpenCASCADE's fonts")
    case = stk.read_case(os.path.join(CASES, "tibia-osteotomy.json"))
    assert [(l["name"], l["text"], l["mode"]) for l in case["labels"]] == [("case", "TIBIA L1", "engrave")]
    path = tmp_path / "case.json"
    stk.write_case(case, str(path))
    again = stk.read_case(str(path))
    assert again["labels"][0]["text"] == "TIBIA L1" and np.allclose(again["labels"][0]["at"], case["labels"][0]["at"])
    with pytest.raises(ValueError, match=r"labels\[0\]\.depth"):
        stk.write_case(dict(case, labels=[dict(case["labels"][0], depth=0.2)]), str(tmp_path / "bad.json"))
    v, f = stk.read_mesh(case["bone"])
    args = dict(clearance=case["clearance"], inside=case["inside"], tubes=case["tubes"], slots=case["slots"])
    r = stk.design_template(v, f, case["boundary_points"], case["thickness"], labels=case["labels"], **args)
    assert r["solid"]["valid"], r["solid"]["summary"]
    assert r["counts"]["labels"] == 1
    label = r["labels"][0]
    assert label["text"] == "TIBIA L1" and label["depth"] == pytest.approx(0.6)
    assert label["height"] == pytest.approx(3.5, abs=0.05), "cap height as planned"
    assert label["min_wall"] >= case["thickness"] - 0.6 - 0.05 * case["thickness"]
    assert label["min_clearance"] >= 1.0
    plain = stk.design_template(v, f, case["boundary_points"], case["thickness"], **args)
    assert plain["solid"]["volume"] - r["solid"]["volume"] > 5.0, "the engraving takes material"
    far = dict(case["labels"][0], name="far", at=[0.0, 0.0, 0.0])
    with pytest.raises(RuntimeError, match="label 'far'"):
        stk.design_template(v, f, case["boundary_points"], case["thickness"], labels=[far], **args)


def test_blade_presets_of_the_catalogue_and_of_a_users_file(stk, tmp_path):
    """The catalogue's saw blades (its own section), and a user's catalogue with its own blade, checked by key."""
    blades = {b["name"]: b for b in stk.blade_presets()}
    assert blades["sagittal-1.27"]["thickness"] == pytest.approx(1.27)
    assert blades["micro-0.4"]["clearance"] == pytest.approx(0.1)
    mine = tmp_path / "mine.json"
    mine.write_text('{"format": "surgical-template-sleeves/1", "sleeves": [], '
                    '"blades": [{"name": "vendor-0.7", "thickness": 0.7, "clearance": 0.05}]}')
    assert stk.blade_presets(str(mine)) == [{"name": "vendor-0.7", "description": "", "thickness": 0.7,
                                             "clearance": 0.05}]
    mine.write_text('{"format": "surgical-template-sleeves/1", "sleeves": [], "blades": [{"name": "v"}]}')
    with pytest.raises(ValueError, match=r"blades\[0\]\.thickness"):
        stk.blade_presets(str(mine))


def test_pins_from_presets_and_the_direction_into_the_bone(stk):
    """A pin preset makes a pin tube with its counterbore; a pin planned by its entry only gets the
    direction into the bone there (against the surface's normal)."""
    screw = stk.find_sleeve_preset(stk.sleeve_presets(), "pin-screw-2.7")
    assert screw["kind"] == "pin" and screw["counterbore"]["radius"] == pytest.approx(2.6)
    tube = stk.tube_from_axis({"name": "p", "entry": [0, 0, 0], "direction": [0, 0, -1]}, screw)
    assert tube["kind"] == "pin" and tube["counterbore"]["depth"] == pytest.approx(3.0)
    # A tilted plane z = 0.5 x: outward normal (-0.5, 0, 1) / |.|; into the bone is its opposite.
    xs = np.linspace(-10, 10, 21)
    v = np.array([[x, y, 0.5 * x] for y in xs for x in xs])
    f = []
    for j in range(20):
        for i in range(20):
            a = j * 21 + i
            f += [[a, a + 1, a + 22], [a, a + 22, a + 21]]
    d = stk.pin_direction(v, np.array(f), [0.0, 0.0, 0.0], 1.5)
    assert np.dot(d, -np.array([-0.5, 0.0, 1.0]) / np.sqrt(1.25)) > 0.9999
    with pytest.raises(RuntimeError, match="tube 'far'"):
        stk.pin_direction(v, np.array(f), [0.0, 0.0, 50.0], 1.5, "far")

"""Plans through the workbench API headless: 3D Slicer markups onto a bare bone (LPS and RAS), a CSV of
axes onto a template, bad plans refused without a change, a markups case round trip, the user's
sleeve catalogue."""
import pytest

from fc_session import run_headless


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(tmp_path_factory, "plan_headless.py")


def valid(s):
    return s["valid"] and s["components"] == 1 and s["volume"] > 0


def test_slicer_plan_on_a_bare_bone_builds_the_guide(run):
    r = run["on_bone"]
    assert r["space"] == "LPS"
    assert valid(r["solid"])
    assert r["tubes"] == ["left", "right"]
    assert r["depths"] == pytest.approx([35.0, 35.0], abs=1e-3)
    assert r["inner_radii"] == pytest.approx([r["preset_inner_radius"]] * 2)
    assert r["point_error"] < 1e-4 and r["inside_error"] < 1e-4  # RAS markups converted into the LPS bone


def test_the_import_is_one_undo_step(run):
    assert run["on_bone"]["after_undo"] == ["Bone"]


def test_slicer_plan_on_a_ras_bone_lands_mirrored(run):
    r = run["on_ras_bone"]
    assert r["space"] == "RAS"
    assert valid(r["solid"])
    assert r["point_error"] < 1e-4 and r["entry_error"] < 1e-4


def test_csv_axes_give_the_case_files_guide(run):
    r = run["csv"]
    assert r["tubes"] == ["16", "13", "11", "23", "26"]
    assert r["depths"] == pytest.approx([10.0] * 5, abs=1e-3)
    assert r["on_the_template"] and r["boundaries"] == 1  # put on the bone: its template found, nothing duplicated
    assert valid(r["solid"])
    assert r["solid"]["volume"] == pytest.approx(r["reference"]["volume"], rel=1e-4)


@pytest.mark.parametrize("tag, words", [
    ("no_sizes", ["vertebra-plan.mrk.json", "axis \"left\"", "no inner_radius"]),
    ("bad_csv", ["bad.csv:3", "entry_y", "oops"]),
    ("bad_markups", ["bad.mrk.json", "markups[0] (Line)", "2 defined control points"]),
    ("bad_preset", ["no-such-sleeve", "pilot-2.0"]),
    ("no_blade", ["tibia-flap-planes.mrk.json", "plane \"proximal plane\"", "no blade"]),
    ("taken", ["plane \"proximal plane\"", "has a slot of that name"]),
])
def test_bad_plans_change_nothing(run, tag, words):
    r = run[tag]
    assert r["raised"], tag
    assert r["unchanged"], tag
    for w in words:
        assert w in r["message"], (w, r["message"])


def test_markups_case_round_trip(run):
    r = run["roundtrip"]
    assert r["points"] < 1e-9
    for name, entry, direction, depth_a, depth_b, same_inner, same_length in r["tubes"]:
        assert entry < 1e-9 and direction < 1e-9 and same_inner and same_length, name
        assert depth_b == pytest.approx(depth_a, abs=1e-9) and depth_a == pytest.approx(35.0, abs=1e-3)
    assert r["volumes"][1] == pytest.approx(r["volumes"][0], rel=1e-9)


def test_user_catalogue_extends_the_projects(run):
    r = run["presets"]
    assert "my-sleeve" in r["names"] and "kwire-2.0" in r["names"]
    assert r["mine"]["inner_radius"] == pytest.approx(1.0) and r["mine"]["offset"] == 0.0
    assert r["replaced"]["inner_radius"] == pytest.approx(1.1)  # the user's pilot-2.0 replaces the project's
    assert r["tube"][:4] == pytest.approx([1.0, 2.5, 7.0, 0.0]) and r["tube"][4] == "my-sleeve"


def test_a_failing_step_leaves_nothing_without_undo(run):
    assert run["failed_step_objects"] == []


def test_slicer_cut_planes_become_slots_into_the_bone(run):
    r = run["planes"]
    assert valid(r["solid"]), r["status"]
    assert [s[0] for s in r["slots"]] == ["proximal plane", "distal plane"]
    for name, direction, blade, clearance, length in r["slots"]:
        assert direction is None, name  # the saw's travel is the kernel's, into the bone
        assert (blade, clearance, length) == pytest.approx((0.89, 0.1, 14.0)), name
    assert [s[1] is None for s in r["saved"]] == [True, True]  # saved as planned: without a travel

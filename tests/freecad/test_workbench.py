"""The workbench's API headless in FreeCAD: a guide built from a case file, changed parametrically,
undone and redone, failing and repaired, saved and restored, and written back as a case file."""
import os

import pytest

from fc_session import ROOT, run_headless


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(tmp_path_factory, "workbench_headless.py",
                        ST_CASE=os.path.join(ROOT, "examples", "cases", "sacrum-iliosacral.json"))


def valid(r):
    return r["valid"] and r["components"] == 1 and r["volume"] > 0


def test_case_builds_a_parametric_tree_with_a_valid_guide(run):
    assert valid(run["loaded"])
    assert run["tree"]["tubes"] == ["IS1"]
    assert run["tree"]["tube_is_solid"]
    assert run["tree"]["thickness"] == pytest.approx(3.0)


def test_parameters_drive_the_guide(run):
    assert valid(run["wider_sleeve"]) and valid(run["thicker"])
    assert run["wider_sleeve"]["volume"] > run["loaded"]["volume"] + 1.0
    assert run["thicker"]["volume"] > run["wider_sleeve"]["volume"] + 50.0


def test_undo_and_redo(run):
    assert valid(run["thinner"]) and run["thinner"]["volume"] < run["thicker"]["volume"]
    assert run["after_undo_thickness"] == pytest.approx(4.0)
    assert run["undone"]["volume"] == pytest.approx(run["thicker"]["volume"], rel=1e-9)
    assert run["after_redo_thickness"] == pytest.approx(2.0)


def test_a_failing_kernel_call_leaves_the_document_usable(run):
    assert "Invalid" in run["failed"]["state"]
    assert run["failed"]["facets"] == run["thicker"]["facets"]  # the last good guide stays
    assert valid(run["repaired"])
    assert run["repaired"]["volume"] == pytest.approx(run["thicker"]["volume"], rel=1e-9)


def test_save_and_restore_recompute_identically(run):
    assert run["restored_facets"] == run["repaired"]["facets"]
    assert valid(run["reopened"])
    assert run["reopened"]["volume"] == pytest.approx(run["repaired"]["volume"], rel=1e-9)


def test_case_round_trip(run):
    case = run["roundtrip_case"]
    assert case["format"] == "surgical-template-case/1"
    assert case["template"]["thickness"] == pytest.approx(4.0)
    assert case["tubes"][0]["outer_radius"] == pytest.approx(3.8)
    assert valid(run["roundtrip"])
    assert run["roundtrip"]["volume"] == pytest.approx(run["reopened"]["volume"], rel=1e-9)


def test_insertion_is_kept_by_cases_and_measured(run):
    ins = run["insertion"]
    # The example case has no template.insertion: the template makes no analysis, and saving keeps it so.
    assert ins["loaded"] == "None" and ins["roundtrip"] == "None"
    assert "insertion" not in run["roundtrip_case"]["template"]
    # Asked for the least-undercut direction, the template reports its undercut; the case says "auto".
    assert ins["auto_case"] == "auto"
    assert "undercut" in ins["auto_status"]
    assert ins["auto_undercut"] >= 0.0
    # The direction used is kept on the template, and Validate's removal check agrees with the design's.
    assert abs(sum(c * c for c in ins["auto_used"]) - 1.0) < 1e-6
    assert ins["inspect_removable"] == ins["auto_removable"]
    # The stability score is kept on the template and repeated on the guide; Validate measures it again
    # on the template's mesh (its inner facets, block-out fills included, float32): close to the design's.
    stab = ins["stability"]
    assert 0.0 <= stab["template"] <= 1.0 and stab["guide"] == stab["template"]
    assert stab["contacts"] > 100 and abs(stab["inspect"] - stab["template"]) < 0.1
    # set_insertion (the "Insertion from view" command's call) makes the template use that direction.
    assert ins["set_mode"] == "Direction"
    assert ins["set_used"] == pytest.approx([0, 0, -1], abs=1e-9)


def test_a_cutting_guide_case_loads_with_its_pins_slots_and_label(run):
    """The tibia example (two saw slots, two pins, a label): the pins become tubes of kind pin, the one
    planned without a direction gets the kernel's (into the bone from its entry), the screw keeps its
    counterbore; the slots are cut and the label engraved in the guide (it loses material with each) and
    a case saved from the guide keeps slots, kinds, counterbore and label."""
    tree = run["tibia_tree"]
    assert tree["tubes"] == ["proximal pin", "distal screw"]
    assert tree["kinds"] == ["pin", "pin"] and tree["saved_kinds"] == ["pin", "pin"]
    assert tree["counterbore"] == [pytest.approx(2.2), pytest.approx(3.0)]
    assert tree["saved_counterbore"] == {"radius": pytest.approx(2.2), "depth": pytest.approx(3.0)}
    d, want = tree["direction"][0], tree["kernel_direction"]
    assert sum(a * b for a, b in zip(d, want)) == pytest.approx(1.0, abs=1e-6)
    assert tree["slots"] == ["proximal cut", "distal cut"] and tree["saved_slots"] == tree["slots"]
    assert valid(run["tibia"]) and valid(run["tibia_without_slots"])
    assert run["tibia"]["volume"] != pytest.approx(run["tibia_without_slots"]["volume"], rel=1e-3)
    assert tree["labels"] == ["TIBIA L1"] and tree["saved_labels"] == tree["labels"]
    assert valid(run["tibia_without_labels"])
    assert run["tibia_without_labels"]["volume"] > run["tibia"]["volume"] + 5.0, "the engraving takes material"


def test_validate_checks_each_blade_path_and_label_on_the_finished_guide(run):
    """Validate's rows for a cutting guide: both blade paths free on the finished mesh and the label as laid
    (at least its planned 0.6 mm deep, 1 mm or more from sleeves and slots); a chip of material left in a slot
    fails the guide, naming the slot and where."""
    parts = run["tibia_parts"]
    assert parts["passed"]
    rows = {(r["name"], r["check"]): r for r in parts["rows"]}
    for name in ("proximal cut", "distal cut"):
        assert rows[(name, "blade path")]["passed"] and rows[(name, "blade path")]["result"].startswith("free")
    labels = [r for r in parts["rows"] if r["check"] == 'engrave "TIBIA L1"']
    assert len(labels) == 1 and "0.60 mm deep" in labels[0]["result"]
    chipped = parts["chipped"]
    assert not chipped["passed"]
    assert "blade path blocked in slot 'proximal cut'" in chipped["summary"]
    first = [r for r in chipped["rows"] if r["name"] == "proximal cut"][0]
    assert not first["passed"] and first["result"].startswith("BLOCKED near")
    assert [r["passed"] for r in chipped["rows"] if r["name"] == "distal cut"] == [True]


def test_the_protocol_lists_pins_slots_and_labels(run):
    """The tibia guide's protocol: its pins by kind, a table of its saw slots (plane, travel, blade, width
    = blade + 2 x clearance, closed ends) and one of its labels (text, mode, cap height, depth)."""
    tables, current = {}, None
    for line in run["tibia_protocol"].splitlines():
        if line.startswith("|") and not line.startswith("|-"):
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if current is None:
                current = cells[0]
                tables[current] = {"head": cells, "rows": {}}
            else:
                tables[current]["rows"][cells[0]] = dict(zip(tables[current]["head"], cells))
        elif not line.startswith("|"):
            current = None
    assert set(tables) == {"Sleeve", "Slot", "Label"}
    assert {r["Kind"] for r in tables["Sleeve"]["rows"].values()} == {"pin"}
    slots = tables["Slot"]["rows"]
    assert sorted(slots) == ["distal cut", "proximal cut"]
    for r in slots.values():
        assert float(r["Width"]) == pytest.approx(0.89 + 2 * 0.1, abs=1e-6) and float(r["Blade"]) == 0.89
        assert r["Closed"] == "start+end"
    assert abs(float(slots["distal cut"]["Normal Y"])) == pytest.approx(0.34202, abs=1e-5)
    label = tables["Label"]["rows"]["case"]
    assert label["Text"] == "TIBIA L1" and label["Mode"] == "engrave"
    assert float(label["Cap height"]) == 3.5 and float(label["Depth"]) == 0.6


def test_labels_and_slots_added_through_the_api(run):
    """add_label engraves the case's name where asked (one undo step); a label too close to a sleeve is
    refused naming it and the sleeve, and the guide stays as it was; add_slot cuts a slot; undo takes it back."""
    a = run["added"]
    assert a["label"]["text"] == "TIB 1" and a["label"]["count"] == 1, "the guide's name by default"
    assert "Invalid" not in a["label"]["state"]
    assert a["refused"] is not None and "label 'label 2'" in a["refused"] and "distal screw" in a["refused"]
    assert a["after_refusal"]["count"] == 1 and "Invalid" not in a["after_refusal"]["state"]
    assert a["after_refusal"]["volume"] == pytest.approx(a["label"]["volume"], rel=1e-9)
    assert a["slot"]["name"] == "slot 3" and a["slot"]["count"] == 3 and "Invalid" not in a["slot"]["state"]
    assert a["after_undo"] == {"slots": 2, "labels": 1}


def test_slots_and_labels_are_objects_of_their_own_with_a_blade_chooser(run):
    """The tibia's two slots and its label are Slot and Label objects (Part features with valid shapes)
    in the guide's Parts; a slot's BladePreset offers the catalogue's blades and sets thickness and
    clearance."""
    objects = run["tibia_tree"]["part_objects"]
    assert [o[0] for o in objects] == ["Slot", "Slot", "Label"]
    assert all(o[2] == "Part::FeaturePython" and o[3] for o in objects)
    b = run["blade_choice"]
    assert b["choices"][0] == "custom" and len(b["choices"]) >= 3 and b["before"][0] in b["choices"]
    assert b["blade"] == pytest.approx(b["catalogue"]["thickness"]) and b["blade"] != pytest.approx(b["before"][1])
    assert b["clearance"] == pytest.approx(b["catalogue"]["clearance"])

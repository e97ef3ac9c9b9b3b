"""The workbench in a real FreeCAD window under Xvfb: activated, a case opened by its command, a
boundary drawn by clicks on the bone and its template made by the commands; the screenshots (kept in
the build's test-output folder) must show the guide in its blue."""
import os

import pytest

from fc_session import ROOT, run_gui


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    return run_gui(tmp_path_factory, "gui_session.py", "gui-result.json",
                   ST_CASE=os.path.join(ROOT, "examples", "cases", "sacrum-iliosacral.json"))


def test_workbench_and_commands(session):
    assert session["workbench"] == "SurgicalTemplateWorkbench"
    for name in ("OpenCase", "ImportBone", "DrawBoundary", "CreateTemplate", "AddTube", "CreateGuide",
                 "AddSlot", "AddLabel", "Validate", "ExportSTL", "SaveCase"):
        assert "SurgicalTemplate_" + name in session["commands"]


def test_case_opened_by_the_command_shows_the_guide(session):
    assert "Invalid" not in session["guide_state"]
    assert "no self-intersection" in session["guide_status"]
    # The guide is visible in its colour (about 2% of the frame; a view of the bone alone has 0%).
    assert session["gui-guide"]["blue"] > 0.01


def test_boundary_drawn_by_clicks_gives_a_template(session):
    assert session["clicks_on_bone"] >= 6  # of the 8 control points; one may hide behind the bone
    assert session["preview_length"] > 50.0
    assert len(session["boundaries"]) == 1
    t = session["drawn_template"]
    assert t["facets"] > 1000 and "Invalid" not in t["state"]
    assert t["thickness"] == pytest.approx(2.8)  # the default set in the preferences
    assert session["gui-drawn-template"]["blue"] > 0.01


def test_tube_added_by_a_click_and_guide_created_by_the_commands(session):
    assert session["tube_click"]
    c = session["continue"]  # OK with "Continue" adds the tube and keeps the panel for the next one
    assert c["closes"] is False and c["open"] and c["tubes"] == 1
    assert c["entry_text"].startswith("click the entry") and c["sizes"] == pytest.approx(c["outer"])
    assert c["closed_by_cancel"] and c["tubes_after_cancel"] == 1
    g = session["drawn_guide"]
    assert g["tubes"] == 1 and g["guides"] == 1
    assert "Invalid" not in g["state"] and "no self-intersection" in g["status"]
    assert session["template_hidden_by_guide"]


def test_boundary_edited_in_its_panel_by_drag_click_and_delete_key(session):
    e = session["edit"]
    assert e["opened_by_double_click"] and e["in_edit"] and e["overlay_shown"]
    n = e["panel_points"]
    assert n == len(e["before"]) and e["nearest_checked"]
    # Dragged: the same count, the point moved onto the bone where the target's view ray meets it.
    d = e["drag"]
    assert e["dragging_started"]
    assert d["count"] == n and d["others_kept"]
    assert d["moved_by"] > 1.0 and d["off_target"] < 0.5
    # Clicked near a segment: one point more, between that segment's two points.
    i = e["insert"]
    assert i["count"] == n + 1 and i["new"] == [i["segment"] + 1]
    assert i["previous_is_segment_start"] and i["next_is_segment_end"] and i["off_click"] < 0.5
    # Delete key in the list: the point goes, FreeCAD's Delete command does not run (the bone stays).
    assert e["delete_key_claimed"] and e["bone_still_there"]
    assert e["delete"]["count"] == n and e["delete"]["removed"]
    # The markers (one selected) and the curve are in the screenshot.
    assert e["marker_pixels"] > 50 and e["selected_pixels"] > 20 and e["curve_pixels"] > 200
    # OK: exactly the edited points, the boundary recomputed, one undo step, nothing left over.
    a = e["after"]
    assert e["ok_button"] and a["as_edited"] and a["count"] == n
    assert a["length"] > 50.0 and a["valid"] and "Invalid" not in a["state"]
    assert a["undo_steps"] == 1 and a["undo_name"] == "Edit boundary"
    assert not a["dialog_open"] and not a["in_edit"] and not a["overlay_left"] and not a["preview_objects"]
    # Undo restores the points drawn before.
    u = e["undone"]
    assert u["as_before"] and u["length"] > 50.0 and u["valid"] and "Invalid" not in u["state"]
    # Cancel leaves the boundary and the undo history alone.
    c = e["cancelled"]
    assert c["unchanged"] and c["undo_steps"] == 0
    assert not c["dialog_open"] and not c["in_edit"] and not c["overlay_left"]


def test_a_label_and_a_slot_added_by_the_commands_at_a_picked_point(session):
    """Add label at a point picked on the tibia guide engraves the case's name there, reading across the view
    (its up perpendicular to the view); Add saw slot from the view adds a slot or, refused, says why and leaves
    the guide as it was; the guide stays valid; each is one undo step."""
    c = session["cutting"]
    assert c["label"]["texts"] == [c["label"]["case"]], c["warnings"]
    assert "Invalid" not in c["label"]["state"]
    assert c["label"]["up"] == pytest.approx([0, 0, 1], abs=1e-6), "the label's up is the view's up"
    assert "Invalid" not in c["slot"]["state"]
    if c["slot"]["after"] == c["slot"]["before"]:  # refused: the undo takes the label back
        assert any("slot 'slot 3'" in w for w in c["warnings"]), c["warnings"]
        assert c["after_undo"] == {"slots": c["slot"]["before"], "labels": 0}
    else:
        assert c["slot"]["after"] == c["slot"]["before"] + 1
        assert c["after_undo"] == {"slots": c["slot"]["before"], "labels": 1}

"""The workbench behaves like FreeCAD's own (issue 15): a document made without the GUI reopens intact in
it, deleting a guide shows its parts again (undo restores it), File > Open and Import read cases and
plans, and a guide is written for printing as 3MF (units kept), STL or OBJ, its sleeves as STEP."""
import os

import pytest

from fc_session import ROOT, run_gui, run_headless


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    return run_headless(tmp_path_factory, "native_headless.py")


@pytest.fixture(scope="module")
def opened(tmp_path_factory, made):
    return run_gui(tmp_path_factory, "native_gui_session.py", "native-result.json", ST_DOC=made["document"], timeout=300)


def test_a_headless_document_hides_the_guides_parts(made):
    hidden = made["hidden"]
    assert [v for k, v in hidden.items() if k != "maxilla-implants"].count(False) == len(hidden) - 1


def test_a_headless_document_opens_in_the_gui_with_its_view_providers(opened):
    providers = opened["view_providers"]
    assert providers and all(p == "ViewProvider" for p in providers.values()), providers
    icons = opened["icons"]
    assert icons["maxilla-implants"] == "SurgicalTemplate_Guide.svg"
    assert {icons[t] for t in ("16", "13", "11", "23", "26")} == {"SurgicalTemplate_Tube.svg"}
    assert "SurgicalTemplate_Template.svg" in icons.values() and "SurgicalTemplate_Boundary.svg" in icons.values()
    # The shell, the five tubes and the case data (the drawing's title block) under the guide.
    assert set(opened["children"]) >= {"16", "13", "11", "23", "26", "maxilla-implants case data"}
    assert len(opened["children"]) == 7
    assert icons["maxilla-implants case data"] == "SurgicalTemplate_CaseInfo.svg"
    visible = opened["visible"]
    assert visible["maxilla-implants"]
    assert not any(visible[t] for t in ("16", "13", "11", "23", "26"))
    shapes = [k for k in opened["children"] if k != "maxilla-implants case data"]
    assert [visible[k] for k in shapes].count(True) == 0


def test_deleting_the_guide_shows_its_parts_and_undo_restores_it(opened):
    gone = opened["after_delete"]
    assert gone["guides"] == 0
    assert all(gone["visible"].values()) and len(gone["visible"]) == 6
    assert opened["after_undo"]["guides"] == 1


def test_file_open_and_import_know_cases_and_plans(made, opened):
    assert "st_import" in opened["import_types"]
    assert made["opened"]["kind"] == "Guide" and made["opened"]["tubes"] == 2
    assert made["opened"]["slots"] == ["proximal plane", "distal plane"]
    assert made["inserted"]["slots"] == ["proximal plane", "distal plane"]
    assert "Invalid" not in made["inserted"]["state"]
    assert "goes on a bone" in made["plan_opened_alone"]


def test_written_for_printing_in_each_format(made):
    files, volume = made["files"], made["guide_volume"]
    assert files["3mf"]["unit"] == "millimeter"
    assert files["3mf"]["volume"] == pytest.approx(volume, rel=1e-7)  # coordinates read back as the same floats
    assert files["stl"]["volume"] == pytest.approx(volume, rel=1e-6)
    assert files["obj"]["size"] > 10_000
    assert files["step"]["solids"] == 5 and files["step"]["volume"] == pytest.approx(files["step"]["tubes"], rel=1e-6)
    assert made["leftovers"] == []
    assert "unknown format 'xyz'" in made["export_errors"]["format"] and "3mf" in made["export_errors"]["format"]
    assert "no sleeves" in made["export_errors"]["step_of_template"]


def test_tubes_dragged_out_of_and_dropped_onto_a_guide(opened):
    r = opened["drag_drop"]
    assert r["can_drag"]
    d = r["dragged"]
    assert d["tubes"] == r["tubes"] - 1 and d["visible"] and d["volume"] < r["volume"] - 1.0
    assert r["can_drop"] == {"tube": True, "bone": False, "template": False}
    e = r["dropped"]
    assert e["tubes"] == r["tubes"] and not e["visible"] and "Invalid" not in e["state"]
    assert e["volume"] == pytest.approx(r["volume"], rel=1e-9)


def test_double_click_on_template_and_guide_opens_their_panels(opened):
    r = opened["template_panel"]
    assert r["double_clicked"] and r["opened"]
    assert r["panel"] == {"thickness": pytest.approx(r["thickness"]), "unit": "mm", "insertion": r["insertion"]}
    assert r["preview"]["thickness"] == pytest.approx(r["thickness"] + 0.5)
    assert r["preview"]["volume"] > r["volume"] * 1.05            # the thicker template on the guide
    assert r["cancelled"]["thickness"] == pytest.approx(r["thickness"]) and not r["cancelled"]["dialog"]
    assert r["cancelled"]["volume"] == pytest.approx(r["volume"], rel=1e-9)
    a = r["accepted"]
    assert a["thickness"] == pytest.approx(r["thickness"] + 0.3) and a["insertion"] == "None"
    assert a["undo_steps"] == 1 and "Invalid" not in a["state"] and a["volume"] > r["volume"]
    assert r["undone"] == {"thickness": pytest.approx(r["thickness"]), "insertion": r["insertion"]}
    g = r["guide_panel"]
    assert g["tolerance"] == pytest.approx(0.01) and "5 tube(s): 16, 13, 11, 23, 26" in g["parts"]


def test_preferences_have_an_icon_and_unit_aware_fields(opened):
    p = opened["preferences"]
    assert p["icon"]
    fields = p["fields"]
    assert {"Thickness", "Clearance", "Resolution", "InnerDiameter", "OuterDiameter", "Length", "Offset",
            "SlotBlade", "SlotLength", "LabelHeight", "LabelDepth"} <= set(fields)
    assert all(unit == "mm" for _, unit in fields.values())
    assert fields["OuterDiameter"][0] == pytest.approx(4.6)       # the stored preference shown


def test_an_outer_diameter_typed_as_an_expression_drives_the_guide(opened):
    """"=Spreadsheet.D" typed in the tube panel's outer diameter (FreeCAD's expression editor opens on
    "="): the tube follows the spreadsheet, and so does the guide."""
    e = opened["expression"]
    assert e["editor_opened"] == 1
    assert e["field"] == {"value": pytest.approx(4.8), "expression": "Spreadsheet.D"}
    assert e["after"]["expressions"] == {"OuterDiameter": "Spreadsheet.D"}
    assert e["after"]["outer"] == pytest.approx(4.8) and "Invalid" not in e["after"]["state"]
    assert e["after"]["volume"] > e["before"]["volume"] + 1.0
    assert e["sheet_changed"]["outer"] == pytest.approx(5.2)
    assert e["sheet_changed"]["volume"] > e["after"]["volume"] + 1.0


def test_double_click_on_a_tube_edits_it_with_a_live_preview(opened):
    e = opened["edit"]
    assert e["double_clicked"] and e["opened"] and e["in_edit"]
    assert e["panel_outer"] == pytest.approx(e["outer"]) and e["panel_unit"] == "mm"
    assert e["preview"]["outer"] == pytest.approx(e["outer"] + 0.5)
    assert e["preview"]["volume"] > e["volume"] + 1.0  # the guide shows the thicker sleeve at once
    assert e["cancelled"]["outer"] == pytest.approx(e["outer"])
    assert e["cancelled"]["volume"] == pytest.approx(e["volume"], rel=1e-9) and not e["cancelled"]["in_edit"]
    assert e["accepted"]["outer"] == pytest.approx(e["outer"] + 0.3) and e["accepted"]["undo_steps"] == 1
    assert e["undone"]["outer"] == pytest.approx(e["outer"])


def test_menu_in_groups_with_shortcuts_toolbars_and_a_context_menu(opened):
    """The menu's three groups (case; design; checks and output) between separators, shortcuts on the
    frequent commands, a toolbar per group, and a right-click on a guide offers what one does with it."""
    menu = opened["menu"]
    texts = [t for t, _ in menu]
    assert texts.count("") == 2
    first, second = texts.index(""), texts.index("", texts.index("") + 1)
    assert "Open case file" in texts[:first] and "Add drilling tube" in texts[first:second]
    assert "Validate" in texts[second:] and "Export for printing" in texts[second:]
    shortcuts = dict(menu)
    assert shortcuts["Add drilling tube"] == "T, T" and shortcuts["Validate"] == "T, V"
    assert len(opened["toolbars"]) == 3 and sum(opened["toolbars"].values()) == len(texts) - 2
    cases = [f[:-5] for f in sorted(os.listdir(os.path.join(ROOT, "examples", "cases"))) if f.endswith(".json")]
    assert opened["examples_menu"] == cases and len(cases) >= 8
    e = opened["example"]   # Open example > tibia-osteotomy: its guide, built
    assert e["documents"] == 1 and e["guides"] == ["tibia-osteotomy"]
    assert "Invalid" not in e["state"] and e["facets"] > 1000
    context = opened["context_menu"]
    for words in ("Add drilling tube", "Add saw slot from view", "Add label", "Validate", "Export for printing"):
        assert words in context, (words, context)

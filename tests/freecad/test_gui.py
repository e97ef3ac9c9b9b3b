"""The workbench in a real FreeCAD window under Xvfb: activated, a case opened by its command, a
boundary drawn by clicks on the bone and its template made by the commands; the screenshots (kept in
the build's test-output folder) must show the guide in its blue."""
import json
import os
import shutil
import subprocess

import pytest

from test_workbench import ROOT, install_workbench


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    if not shutil.which("freecad") or not shutil.which("xvfb-run"):
        pytest.skip("FreeCAD GUI or Xvfb missing")
    home = tmp_path_factory.mktemp("fcgui")
    install_workbench(str(home))
    out = os.path.join(os.environ.get("ST_TEST_OUTPUT_DIR", str(tmp_path_factory.mktemp("out"))), "gui")
    os.makedirs(out, exist_ok=True)
    env = dict(os.environ, FREECAD_USER_HOME=str(home), FREECAD_USER_DATA=str(home), ST_OUT=out,
               QTWEBENGINE_DISABLE_SANDBOX="1",
               ST_CASE=os.path.join(ROOT, "examples", "cases", "sacrum-iliosacral.json"))
    p = subprocess.run(["xvfb-run", "-a", "-s", "-screen 0 1280x1024x24", "freecad",
                        os.path.join(ROOT, "tests", "freecad", "gui_session.py")],
                       capture_output=True, text=True, env=env, timeout=600)
    path = os.path.join(out, "gui-result.json")
    assert os.path.exists(path), p.stdout[-3000:] + p.stderr[-3000:]
    result = json.load(open(path))
    assert not result["errors"], result["errors"]
    return result


def test_workbench_and_commands(session):
    assert session["workbench"] == "SurgicalTemplateWorkbench"
    for name in ("OpenCase", "ImportBone", "DrawBoundary", "CreateTemplate", "AddTube", "CreateGuide",
                 "Validate", "ExportSTL", "SaveCase"):
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
    g = session["drawn_guide"]
    assert g["tubes"] == 1 and g["guides"] == 1
    assert "Invalid" not in g["state"] and "no self-intersection" in g["status"]
    assert session["template_hidden_by_guide"]

"""The workbench's API headless in FreeCAD: a guide built from a case file, changed parametrically,
undone and redone, failing and repaired, saved and restored, and written back as a case file."""
import json
import os
import shutil
import subprocess

import pytest

FREECAD_LIB = "/usr/lib/freecad-python3/lib"
ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def install_workbench(user_data):
    """The workbench and the kernel module in a private FreeCAD user folder, as `make install` does."""
    target = os.path.join(user_data, "Mod", "SurgicalTemplate")
    shutil.copytree(os.path.join(ROOT, "workbench", "SurgicalTemplate"), target)  # .py, .ui, package.xml
    shutil.copytree(os.path.join(ROOT, "icons"), os.path.join(target, "icons"), dirs_exist_ok=True)
    python_dir = os.environ.get("ST_PYTHON_DIR", os.path.join(os.getcwd(), "python"))
    for f in os.listdir(python_dir):
        if f.startswith("stkernel") and f.endswith(".so"):
            shutil.copy(os.path.join(python_dir, f), target)
    return target


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    if not os.path.exists(FREECAD_LIB):
        pytest.skip("FreeCAD is not installed")
    home = tmp_path_factory.mktemp("fc")
    install_workbench(str(home))
    out = tmp_path_factory.mktemp("out")
    env = dict(os.environ, FREECAD_USER_HOME=str(home), FREECAD_USER_DATA=str(home), ST_OUT=str(out),
               ST_CASE=os.path.join(ROOT, "examples", "cases", "sacrum-iliosacral.json"))
    p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tests", "freecad", "workbench_headless.py")],
                       capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    line = [l for l in p.stdout.splitlines() if l.startswith("RESULT ")]
    assert line, p.stdout[-3000:] + p.stderr[-3000:]
    return json.loads(line[0][len("RESULT "):])


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

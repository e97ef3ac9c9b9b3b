"""The command-line tool: designs from case files, reports, refuses bad input without writing."""
import json
import os
import shutil
import subprocess

import pytest

from conftest import EXAMPLES, TOOL

CASES = os.path.join(EXAMPLES, "cases")


def run(*args):
    return subprocess.run([TOOL, *args], capture_output=True, text=True, timeout=600)


def test_design_writes_a_valid_template_and_report(tmp_path):
    out, rep = tmp_path / "t.stl", tmp_path / "r.json"
    p = run("design", os.path.join(CASES, "vertebra-pedicle.json"), "-o", str(out), "--report", str(rep))
    assert p.returncode == 0, p.stderr
    assert out.stat().st_size > 84
    report = json.loads(rep.read_text())
    assert report["solid"]["valid"] and report["solid"]["closed"]
    times = report["times"]
    for key in ("inner_surface_segmentation", "offset_of_inner_surface", "points_for_outer_surface_segmentation",
                "outer_surface_segmentation", "connection_of_inner_and_outer_surfaces", "initial_template_generation"):
        assert times[key] >= 0
    assert report["peak_memory_mb"] > 0
    assert report["counts"]["triangles_of_inner_surface"] > 100
    check = run("check", str(out))
    assert check.returncode == 0, check.stdout + check.stderr


def write_case(tmp_path, **changes):
    case = json.load(open(os.path.join(CASES, "vertebra-pedicle.json")))
    case["bone"] = os.path.join(EXAMPLES, "meshes", "vertebrae_lumbar_L2-L5_ssm_mean.stl.gz")
    for k, v in changes.items():
        if v is None:
            case.pop(k, None)
        else:
            case[k] = v
    path = tmp_path / "case.json"
    path.write_text(json.dumps(case))
    return path


@pytest.mark.parametrize("changes, message", [
    ({"format": "surgical-template-case/2"}, "format"),
    ({"template": {"thickness": -1}}, "template.thickness"),
    ({"template": {"thickness": "thick"}}, "template.thickness"),
    ({"template": {}}, "template.thickness"),
    ({"template": {"thickness": 2, "clearance": -1}}, "template.clearance"),
    ({"boundary": {"points": [[0, 0, 0], [1, 0, 0]]}}, "boundary.points"),
    ({"boundary": {"points": [[0, 0, 0], [1, 0, 0], [0, 1]]}}, "boundary.points[2]"),
    ({"bone": None}, "bone"),
    ({"tubes": [{"entry": [0, 0, 0], "direction": [0, 0, 0], "inner_radius": 1, "outer_radius": 2, "length": 5}]},
     "tubes[0].direction"),
    ({"tubes": [{"entry": [0, 0, 0], "direction": [0, 0, 1], "inner_radius": 2, "outer_radius": 1, "length": 5}]},
     "tubes[0].outer_radius"),
])
def test_invalid_case_is_refused_naming_the_key(tmp_path, changes, message):
    out = tmp_path / "t.stl"
    p = run("design", str(write_case(tmp_path, **changes)), "-o", str(out))
    assert p.returncode == 2, p.stdout + p.stderr
    assert message in p.stderr
    assert not out.exists()


def test_unseparating_loop_fails_without_output(tmp_path):
    # Points far apart on two different vertebrae: not one connected surface part.
    out = tmp_path / "t.stl"
    p = run("design", str(write_case(tmp_path, boundary={"points": [[-31.79, 12.59, 4.04], [-32.5, 4.0, 6.2],
                                                                       [-30, 0, 60], [-30, 10, 60]]})), "-o", str(out))
    assert p.returncode in (1, 2)
    assert "error:" in p.stderr
    assert not out.exists()


@pytest.mark.parametrize("content", [b"", b"solid x\nfacet normal 0 0 1\n", b"\x00" * 84 + b"\x01\x02", b"garbage" * 100])
def test_corrupt_bone_mesh_is_refused(tmp_path, content):
    bone = tmp_path / "bone.stl"
    bone.write_bytes(content)
    out = tmp_path / "t.stl"
    p = run("design", str(write_case(tmp_path, bone=str(bone))), "-o", str(out))
    assert p.returncode == 2, p.stderr
    assert "bone.stl" in p.stderr
    assert not out.exists()


@pytest.mark.parametrize("kind", ["device", "fifo", "directory"])
def test_bone_that_is_not_a_regular_file_is_refused_at_once(tmp_path, kind):
    # /dev/zero was read forever, a FIFO blocked: refused before reading, naming the path.
    bone = {"device": "/dev/zero", "fifo": str(tmp_path / "bone.stl"), "directory": str(tmp_path)}[kind]
    if kind == "fifo":
        os.mkfifo(bone)
    out = tmp_path / "t.stl"
    p = subprocess.run([TOOL, "design", str(write_case(tmp_path, bone=bone)), "-o", str(out)],
                       capture_output=True, text=True, timeout=20)
    assert p.returncode == 2, p.stderr
    assert bone in p.stderr and "not a regular file" in p.stderr or "directory" in p.stderr
    assert not out.exists()


@pytest.mark.parametrize("template, expected", [
    ({"thickness": 1e9}, "template.thickness 1e+09 mm is absurd"),
    ({"thickness": 3, "resolution": 2.0}, "2 mm"),
])
def test_numbers_in_messages_read_as_a_person_writes_them(tmp_path, template, expected):
    p = run("design", str(write_case(tmp_path, template=template)), "-o", str(tmp_path / "t.stl"))
    assert p.returncode == 2, p.stderr
    assert expected in p.stderr
    assert "000000" not in p.stderr


def test_missing_case_file(tmp_path):
    p = run("design", str(tmp_path / "nope.json"))
    assert p.returncode == 2
    assert "nope.json" in p.stderr


def test_case_with_an_overflowing_number_is_refused(tmp_path):
    # Found by fuzz_case: a number too large for a double is a JSON error, not a crash.
    case = tmp_path / "case.json"
    case.write_text('{"format": "surgical-template-case/1", "template": {"thickness": 1' + "7" * 400 + '.5}}')
    p = run("design", str(case), "-o", str(tmp_path / "t.stl"))
    assert p.returncode == 2, p.stderr
    assert "case.json" in p.stderr and "not valid JSON" in p.stderr


def test_labels_come_from_the_font_module_beside_the_tool_and_other_cases_need_none(tmp_path):
    """The tool loads OpenCASCADE's fonts (surgical-template-fonts.so beside it) only for a case with
    labels: a copy of the tool alone designs a case without labels, and refuses one with labels
    naming the module; beside the module, the labels are cut in."""
    alone = tmp_path / "alone"
    alone.mkdir()
    shutil.copy(TOOL, alone / "surgical-template")
    tool = str(alone / "surgical-template")
    plain, labelled = os.path.join(CASES, "vertebra-pedicle.json"), os.path.join(CASES, "tibia-osteotomy.json")
    assert json.load(open(labelled)).get("labels") and not json.load(open(plain)).get("labels")
    p = subprocess.run([tool, "design", plain, "-o", str(tmp_path / "plain.stl")], capture_output=True, text=True,
                       timeout=600)
    assert p.returncode == 0, p.stderr
    out = tmp_path / "labelled.stl"
    p = subprocess.run([tool, "design", labelled, "-o", str(out)], capture_output=True, text=True, timeout=600)
    assert p.returncode == 2
    assert "surgical-template-fonts.so" in p.stderr and str(alone) in p.stderr, p.stderr
    assert not out.exists()
    module = os.path.join(os.path.dirname(TOOL), "surgical-template-fonts.so")
    if not os.path.exists(module):
        pytest.skip("built without OpenCASCADE: no font module")
    shutil.copy(module, alone / "surgical-template-fonts.so")
    rep = tmp_path / "r.json"
    p = subprocess.run([tool, "design", labelled, "-o", str(out), "--report", str(rep)], capture_output=True,
                       text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    report = json.loads(rep.read_text())
    assert report["solid"]["valid"] and report["labels"]

"""Every example case (the paper's four surgical uses and the Slicer-plan variant) designs a guide that
passes the kernel's validation, and the plan commands of the tool read the example plans."""
import glob
import json
import os
import subprocess
import sys

import pytest

from conftest import EXAMPLES, TOOL

CASES = sorted(glob.glob(os.path.join(EXAMPLES, "cases", "*.json")))


def run(*args):
    return subprocess.run([TOOL, *args], capture_output=True, text=True, timeout=600)


@pytest.mark.parametrize("case", CASES, ids=[os.path.basename(c)[:-5] for c in CASES])
def test_example_case_gives_a_valid_guide(tmp_path, case):
    out, rep = tmp_path / "guide.stl", tmp_path / "report.json"
    p = run("design", case, "-o", str(out), "--report", str(rep))
    assert p.returncode == 0, p.stderr
    report = json.loads(rep.read_text())
    assert report["solid"]["valid"] and report["solid"]["components"] == 1
    assert report["counts"]["drilling_tubes"] == len(json.load(open(case)).get("tubes", []))
    check = run("check", str(out))
    assert check.returncode == 0, check.stdout


def test_design_with_a_csv_plan_equals_the_case(tmp_path):
    case = os.path.join(EXAMPLES, "cases", "maxilla-implants.json")
    plan = os.path.join(EXAMPLES, "plans", "maxilla-implants.csv")
    a, b = tmp_path / "a.json", tmp_path / "b.json"
    assert run("design", case, "-o", str(tmp_path / "a.stl"), "--report", str(a)).returncode == 0
    p = run("design", case, "--plan", plan, "-o", str(tmp_path / "b.stl"), "--report", str(b))
    assert p.returncode == 0, p.stderr
    va, vb = (json.loads(x.read_text())["solid"]["volume"] for x in (a, b))
    assert vb == pytest.approx(va, rel=1e-4)  # the CSV's targets are rounded to 0.1 um


def test_design_with_a_slicer_plan_needs_sizes_then_uses_the_preset(tmp_path):
    case = os.path.join(EXAMPLES, "cases", "vertebra-pedicle.json")
    plan = os.path.join(EXAMPLES, "plans", "vertebra-plan.mrk.json")
    p = run("design", case, "--plan", plan, "-o", str(tmp_path / "g.stl"))
    assert p.returncode == 2 and "axis \"left\"" in p.stderr and "preset" in p.stderr
    assert not (tmp_path / "g.stl").exists()
    rep = tmp_path / "r.json"
    p = run("design", case, "--plan", plan, "--preset", "drill-2.5", "-o", str(tmp_path / "g.stl"), "--report", str(rep))
    assert p.returncode == 0, p.stderr
    r = json.loads(rep.read_text())
    assert r["solid"]["valid"] and [t["name"] for t in r["tubes"]] == ["left", "right"]


def test_plan_command_prints_case_keys_in_the_bones_frame():
    plan = os.path.join(EXAMPLES, "plans", "vertebra-plan.mrk.json")
    lps = json.loads(run("plan", plan, "--preset", "kwire-2.0").stdout)
    ras = json.loads(run("plan", plan, "--space", "RAS").stdout)
    case = json.load(open(os.path.join(EXAMPLES, "cases", "vertebra-pedicle.json")))
    assert lps["space"] == "LPS" and ras["space"] == "RAS"
    flat = lambda points: [x for p in points for x in p]  # noqa: E731
    assert flat(lps["boundary"]["points"]) == pytest.approx(flat(case["boundary"]["points"]))
    assert ras["boundary"]["points"][0] == pytest.approx([-x for x in case["boundary"]["points"][0][:2]] +
                                                         [case["boundary"]["points"][0][2]])
    assert lps["tubes"][0]["inner_radius"] == pytest.approx(1.05) and "inner_radius" not in ras["tubes"][0]
    assert lps["tubes"][0]["depth"] == pytest.approx(35.0, abs=1e-3)


def test_plan_errors_name_the_file_and_line(tmp_path):
    bad = tmp_path / "axes.csv"
    bad.write_text("name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z\nA,1,2\n")
    p = run("plan", str(bad))
    assert p.returncode == 2 and "axes.csv:2: has 3 fields" in p.stderr
    p = run("plan", str(tmp_path / "missing.mrk.json"))
    assert p.returncode == 2 and "cannot open" in p.stderr
    p = run("design", os.path.join(EXAMPLES, "cases", "vertebra-pedicle.json"), "--preset", "nope",
            "--plan", os.path.join(EXAMPLES, "plans", "vertebra-plan.mrk.json"), "-o", str(tmp_path / "x.stl"))
    assert p.returncode == 2 and "no sleeve preset \"nope\"" in p.stderr


def test_presets_command_lists_the_catalogue(tmp_path):
    p = run("presets")
    assert p.returncode == 0 and "pilot-2.0" in p.stdout and "kwire-2.0" in p.stdout
    assert "sagittal-0.89" in p.stdout and "1.09" in p.stdout, "the blades and their slot widths"
    mine = tmp_path / "mine.json"
    mine.write_text('{"format": "surgical-template-sleeves/1", "sleeves": [{"name": "x", "inner_diameter": 1, '
                    '"outer_diameter": 0.5, "length": 3}]}')
    p = run("presets", "--presets", str(mine))
    assert p.returncode == 2 and "sleeves[0].outer_diameter" in p.stderr


def test_table1_summary_of_the_four_cases(tmp_path):
    build = os.path.dirname(TOOL)
    p = subprocess.run([sys.executable, os.path.join(EXAMPLES, "table1.py"), "--build", build, "--out", str(tmp_path)],
                       capture_output=True, text=True, timeout=900)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert "maxilla-implants" in lines[0] and "tibia-osteotomy" in lines[0]
    valid = [l for l in lines if l.startswith("| Valid solid")][0]
    assert valid.count("| yes") == 4

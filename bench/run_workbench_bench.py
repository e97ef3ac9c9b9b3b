#!/usr/bin/env python3
"""Benchmark of the workbench in FreeCAD (headless): what a user waits for inside FreeCAD.

Installs the workbench and the kernel module from the build into a private FreeCAD user folder, then
runs, in /usr/bin/python3 with FreeCAD, for each example case with drilling tubes: opening the case
(the whole parametric tree, recomputed), a thickness change, a sleeve radius change (each recomputing
the guide), the inspection behind Validate, the STL export; a 3D Slicer plan put on a bare bone; and
the documentation drawing (PDF and SVG, FreeCAD's GUI under Xvfb). Median of several runs per step,
printed as a Markdown table; --write stores it in bench/results-workbench.md.

    /usr/bin/python3 bench/run_workbench_bench.py --build build [--runs 5] [--drawing-runs 3] [--write]
"""
import argparse
import json
import os
import platform
import shutil
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CASES = ["maxilla-implants", "vertebra-pedicle", "sacrum-iliosacral"]

STEPS = [
    ("load_case", "Open case (bone, boundary, template, tubes, guide)"),
    ("thickness", "Thickness +0.5 mm, recompute (template + guide)"),
    ("outer_radius", "One sleeve's outer radius +0.2 mm, recompute (tube + guide)"),
    ("inspect", "Validate: inspection (solid, seating, bores, thickness map)"),
    ("export", "Export STL"),
    ("load_plan", "Import plan: Slicer markups on a bare bone (boundary, template, tubes, guide)"),
    ("drawing", "Documentation drawing, headless (PDF + SVG + protocol)"),
]

CHILD = r'''
import json, os, statistics, sys, tempfile, time
sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App
import SurgicalTemplate as st

examples, runs, drawing_runs = os.environ["ST_EXAMPLES"], int(os.environ["ST_RUNS"]), int(os.environ["ST_DRAWING_RUNS"])
out = tempfile.mkdtemp()
result = {}


def timed(f):
    start = time.perf_counter()
    value = f()
    return time.perf_counter() - start, value


for name in os.environ["ST_CASES"].split(","):
    case = os.path.join(examples, "cases", name + ".json")
    times = {k: [] for k in ("load_case", "thickness", "outer_radius", "inspect", "export")}
    for run in range(runs):
        seconds, guide = timed(lambda: st.load_case(case))
        times["load_case"].append(seconds)
        doc = guide.Document

        def thicker():
            guide.Shell.Thickness = guide.Shell.Thickness.Value + 0.5
            doc.recompute()

        def wider():
            guide.Tubes[0].OuterDiameter = guide.Tubes[0].OuterDiameter.Value + 0.4
            doc.recompute()

        times["thickness"].append(timed(thicker)[0])
        times["outer_radius"].append(timed(wider)[0])
        seconds, report = timed(lambda: st.inspect(guide, show=False))
        assert report["passed"], report["summary"]
        times["inspect"].append(seconds)
        times["export"].append(timed(lambda: st.export(guide, os.path.join(out, name + ".stl")))[0])
        if run == 0 and name == "maxilla-implants":
            drawing = []
            for _ in range(drawing_runs):
                drawing.append(timed(lambda: st.make_drawing(guide, os.path.join(out, name + ".pdf")))[0])
            result.setdefault("drawing", {})[name] = statistics.median(drawing)
        App.closeDocument(doc.Name)
    for k, v in times.items():
        result.setdefault(k, {})[name] = statistics.median(v)

plan = os.path.join(examples, "plans", "vertebra-plan.mrk.json")
bone_file = os.path.join(examples, "meshes", "vertebrae_lumbar_L2-L5_ssm_mean.stl.gz")
plan_times = []
for run in range(runs):
    doc = App.newDocument("PlanBench")
    bone = st.make_bone(bone_file, doc)
    doc.recompute()
    seconds, guide = timed(lambda: st.load_plan(plan, bone, preset="drill-2.5"))
    assert "Invalid" not in guide.State
    plan_times.append(seconds)
    App.closeDocument(doc.Name)
result["load_plan"] = {"vertebra-pedicle": statistics.median(plan_times)}
print("RESULT " + json.dumps(result))
'''


def install(build, user_data):
    target = os.path.join(user_data, "Mod", "SurgicalTemplate")
    shutil.copytree(os.path.join(ROOT, "workbench", "SurgicalTemplate"), target)
    shutil.copytree(os.path.join(ROOT, "icons"), os.path.join(target, "icons"), dirs_exist_ok=True)
    python_dir = os.path.join(build, "python")
    for f in os.listdir(python_dir):
        if f.startswith("stkernel") and f.endswith(".so"):
            shutil.copy(os.path.join(python_dir, f), target)


def table(result, runs, drawing_runs):
    lines = [f"| step (median of {runs}; drawing of {drawing_runs}) | " + " | ".join(CASES) + " |",
             "|---|" + "---:|" * len(CASES)]
    for key, label in STEPS:
        cells = []
        for case in CASES:
            value = result.get(key, {}).get(case)
            cells.append("-" if value is None else f"{value:.3f} s")
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--drawing-runs", type=int, default=3)
    ap.add_argument("--write", action="store_true")
    args = ap.parse_args()
    user = tempfile.mkdtemp(prefix="st-bench-fc-")
    try:
        install(os.path.abspath(args.build), user)
        env = dict(os.environ, FREECAD_USER_DATA=user, FREECAD_USER_HOME=user, ST_EXAMPLES=os.path.join(ROOT, "examples"),
                   ST_RUNS=str(args.runs), ST_DRAWING_RUNS=str(args.drawing_runs), ST_CASES=",".join(CASES))
        p = subprocess.run(["/usr/bin/python3", "-c", CHILD], capture_output=True, text=True, env=env, timeout=3600)
    finally:
        shutil.rmtree(user, ignore_errors=True)
    line = [l for l in p.stdout.splitlines() if l.startswith("RESULT ")]
    if p.returncode != 0 or not line:
        sys.stderr.write(p.stdout[-3000:] + p.stderr[-3000:])
        return 1
    result = json.loads(line[0][len("RESULT "):])
    cpu = platform.processor() or platform.machine()
    text = (f"Machine: {os.cpu_count()} cores ({cpu}), FreeCAD 0.20.2 headless (/usr/bin/python3), "
            "the workbench's API as a macro calls it.\n\n" + table(result, args.runs, args.drawing_runs))
    print(text)
    if args.write:
        with open(os.path.join(HERE, "results-workbench.md"), "w") as f:
            f.write("# Workbench benchmark\n\nGenerated by `make bench` (bench/run_workbench_bench.py).\n\n" + text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The paper's four surgical cases designed with the command-line tool, summarised like its Table 1.

    /usr/bin/python3 examples/table1.py [--build build] [--out out/examples]

For each case (oral implantology on the maxilla, pedicle screws on a vertebra, an iliosacral screw on
the sacrum, an osteotomy guide on the tibia) it runs `surgical-template design` with a report, checks
the written STL with `surgical-template check`, and prints one Markdown table: the scale of the input
and of the template, the seconds of each step (one run; bench/ has medians) and whether the guide
is a valid solid. Exits 1 if any case fails.
"""
import argparse
import json
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)

CASES = [
    ("Oral implantology", "maxilla-implants"),
    ("Pedicle screws", "vertebra-pedicle"),
    ("Iliosacral screw", "sacrum-iliosacral"),
    ("Osteotomy", "tibia-osteotomy"),
]

ROWS = [
    ("Sampling step", lambda r: r["counts"]["sampling_step"]),
    ("Triangles of input mesh", lambda r: r["input"]["triangles"]),
    ("Points of input mesh", lambda r: r["input"]["points"]),
    ("Edge points of inner surface", lambda r: r["counts"]["edge_points_of_inner_surface"]),
    ("Triangles of inner surface", lambda r: r["counts"]["triangles_of_inner_surface"]),
    ("Points of inner surface", lambda r: r["counts"]["points_of_inner_surface"]),
    ("Drilling tubes", lambda r: r["counts"]["drilling_tubes"]),
    ("Triangles of the guide", lambda r: r["counts"]["template_triangles"]),
    ("Volume of the guide (mm^3)", lambda r: f"{r['solid']['volume']:.0f}"),
    ("Inner surface segmentation (s)", lambda r: r["times"]["inner_surface_segmentation"]),
    ("Offset of inner surface (s)", lambda r: r["times"]["offset_of_inner_surface"]),
    ("Points for outer surface segmentation (s)", lambda r: r["times"]["points_for_outer_surface_segmentation"]),
    ("Outer surface segmentation (s)", lambda r: r["times"]["outer_surface_segmentation"]),
    ("Connection of inner and outer surfaces (s)", lambda r: r["times"]["connection_of_inner_and_outer_surfaces"]),
    ("Initial template generation (s)", lambda r: r["times"]["initial_template_generation"]),
    ("Boolean operation (s)", lambda r: r["times"].get("boolean_operation") if r["counts"]["drilling_tubes"] else None),
    ("Valid solid (closed, 2-manifold, no self-intersection)", lambda r: r["check"]),
]


def cell(value):
    if value is None:
        return "-"
    if isinstance(value, float):
        return f"{value:.3f}"
    return str(value)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--build", default=os.path.join(ROOT, "build"))
    parser.add_argument("--out", default=os.path.join(ROOT, "out", "examples"))
    args = parser.parse_args()
    tool = os.path.join(args.build, "surgical-template")
    os.makedirs(args.out, exist_ok=True)
    reports, failed = [], []
    for title, name in CASES:
        case = os.path.join(HERE, "cases", name + ".json")
        stl = os.path.join(args.out, name + ".stl")
        report = os.path.join(args.out, name + ".json")
        p = subprocess.run([tool, "design", case, "-o", stl, "--report", report], capture_output=True, text=True)
        if p.returncode != 0:
            failed.append(f"{name}: {p.stderr.strip()}")
            continue
        check = subprocess.run([tool, "check", stl], capture_output=True, text=True)
        r = json.load(open(report))
        r["check"] = "yes" if check.returncode == 0 and r["solid"]["valid"] else "NO: " + check.stdout.strip()
        if check.returncode != 0:
            failed.append(f"{name}: {check.stdout.strip()}")
        reports.append((title, name, r))
    print("| | " + " | ".join(f"{t} ({n})" for t, n, _ in reports) + " |")
    print("|---|" + "---|" * len(reports))
    for label, get in ROWS:
        print(f"| {label} | " + " | ".join(cell(get(r)) for _, _, r in reports) + " |")
    print(f"\nSTL files and reports in {os.path.relpath(args.out, os.getcwd())}/")
    for f in failed:
        print("FAILED " + f, file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())

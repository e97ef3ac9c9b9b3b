#!/usr/bin/env python3
"""Benchmark of the initial template: per-step median times next to the paper's Table 1.

Runs `surgical-template design` several times per case (the example cases on the real meshes, and
the same meshes refined by midpoint subdivision to about 0.2M, 0.5M and 1M triangles), takes the
median of every step, and prints a Markdown table; --write stores it in bench/results.md.

    /usr/bin/python3 bench/run_bench.py --build build [--runs 5] [--write]
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(HERE)
CASES = os.path.join(ROOT, "examples", "cases")
BUILD = os.path.join(ROOT, "build")

ROWS = [
    ("inner_surface_segmentation", "Inner surface segmentation"),
    ("offset_of_inner_surface", "Offset of inner surface"),
    ("points_for_outer_surface_segmentation", "Points for outer surface segmentation"),
    ("outer_surface_segmentation", "Outer surface segmentation"),
    ("connection_of_inner_and_outer_surfaces", "Connection of inner and outer surfaces"),
    ("initial_template_generation", "Initial template generation"),
]

# The paper's Table 1 (Intel i5-3210M, 2012): input triangles and seconds per step.
PAPER = {
    "oral, 213k": (213410, [7.956, 11.793, 7.301, 3.557, 0.609, 31.216]),
    "iliosacral, 1.07M": (1073058, [13.837, 1.576, 5.787, 2.403, 0.203, 23.806]),
    "cervical, 38k": (38082, [0.796, 1.357, 2.683, 3.011, 0.141, 7.988]),
    "osteotomy, 149k": (149054, [2.028, 1.778, 6.614, 4.758, 0.187, 15.365]),
}

# (case file, refinement levels): each level splits every triangle in four.
SCALED = [("tibia-osteotomy.json", 1), ("sacrum-iliosacral.json", 1), ("maxilla-implants.json", 1),
          ("tibia-osteotomy.json", 2), ("sacrum-iliosacral.json", 2)]


def refine(path_in, path_out, levels):
    sys.path.insert(0, os.path.join(BUILD, "python"))
    import numpy as np
    import stkernel

    V, F = stkernel.read_mesh(path_in)
    for _ in range(levels):
        e = np.concatenate([F[:, [0, 1]], F[:, [1, 2]], F[:, [2, 0]]])
        key = np.sort(e, axis=1)
        uniq, inv = np.unique(key, axis=0, return_inverse=True)
        mids = len(V) + inv.reshape(3, -1).T  # (m, 3): midpoints of edges 01, 12, 20
        V = np.concatenate([V, 0.5 * (V[uniq[:, 0]] + V[uniq[:, 1]])])
        a, b, c = F[:, 0], F[:, 1], F[:, 2]
        ab, bc, ca = mids[:, 0], mids[:, 1], mids[:, 2]
        F = np.concatenate([np.stack([a, ab, ca], 1), np.stack([b, bc, ab], 1), np.stack([c, ca, bc], 1),
                            np.stack([ab, bc, ca], 1)])
    stkernel.write_stl(V, F, path_out)
    return len(F)


def run_reference(ref, case_path, runs, workdir):
    out = os.path.join(workdir, "ref.json")
    p = subprocess.run([ref, case_path, "--runs", str(runs), "--json", out], capture_output=True, text=True)
    if p.returncode != 0 or not os.path.exists(out):
        return None, (p.stderr or p.stdout).strip()[-200:]
    rep = json.load(open(out))
    os.remove(out)
    if rep.get("failed"):
        return None, rep["failed"]
    return rep, None


def run_case(tool, case_path, runs, workdir):
    reports = []
    for i in range(runs):
        out = os.path.join(workdir, "t.stl")
        rep = os.path.join(workdir, "r.json")
        p = subprocess.run([tool, "design", case_path, "-o", out, "--report", rep], capture_output=True, text=True)
        if p.returncode != 0:
            return None, p.stderr.strip()
        reports.append(json.load(open(rep)))
    med = {k: statistics.median(r["times"][k] for r in reports) for k, _ in ROWS}
    return {"times": med, "report": reports[0],
            "peak_mb": statistics.median(r["peak_memory_mb"] for r in reports)}, None


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--no-scaled", action="store_true")
    ap.add_argument("--reference", help="path of reference-chain (VTK + OpenVDB) to run side by side")
    args = ap.parse_args()
    global BUILD
    BUILD = args.build
    tool = os.path.join(args.build, "surgical-template")
    results = []
    references = []
    with tempfile.TemporaryDirectory() as work:
        for name in sorted(os.listdir(CASES)):
            if name.endswith(".json"):
                r, err = run_case(tool, os.path.join(CASES, name), args.runs, work)
                results.append((name[:-5], r, err))
                print(name, "done" if r else err, file=sys.stderr)
                if args.reference:
                    ref, ref_err = run_reference(args.reference, os.path.join(CASES, name), args.runs, work)
                    references.append((name[:-5], ref, ref_err))
        if not args.no_scaled:
            for name, levels in SCALED:
                case = json.load(open(os.path.join(CASES, name)))
                bone_in = os.path.normpath(os.path.join(CASES, case["bone"]))
                bone_out = os.path.join(work, f"{name}-{levels}.stl")
                n = refine(bone_in, bone_out, levels)
                case["bone"] = bone_out
                cpath = os.path.join(work, f"{name}-{levels}.json")
                json.dump(case, open(cpath, "w"))
                r, err = run_case(tool, cpath, args.runs, work)
                results.append((f"{name[:-5]} x{4 ** levels} ({n / 1e6:.2f}M)", r, err))
                if args.reference:
                    ref, ref_err = run_reference(args.reference, cpath, args.runs, work)
                    references.append((f"{name[:-5]} x{4 ** levels} ({n / 1e6:.2f}M)", ref, ref_err))
                print(name, levels, "done" if r else err, file=sys.stderr)

    lines = ["| case | input triangles | inner triangles | rim points | " +
             " | ".join(label for _, label in ROWS) + " | peak MB |",
             "|---|" + "---:|" * (len(ROWS) + 4)]
    for name, r, err in results:
        if r is None:
            lines.append(f"| {name} | failed: {err} |")
            continue
        rep = r["report"]
        lines.append(f"| {name} | {rep['input']['triangles']:,} | {rep['counts']['triangles_of_inner_surface']:,} | "
                     f"{rep['counts']['edge_points_of_inner_surface']:,} | " +
                     " | ".join(f"{r['times'][k]:.3f}" for k, _ in ROWS) + f" | {r['peak_mb']:.0f} |")
    for name, ref, err in references:
        if ref is None:
            lines.append(f"| VTK+OpenVDB: {name} | failed: {err} |")
            continue
        valid = "valid" if ref.get("solid", {}).get("valid") else "INVALID shell"
        lines.append(f"| VTK+OpenVDB: {name} ({valid}) | {ref.get('bone_triangles', 0):,} | "
                     f"{ref.get('counts', {}).get('inner_triangles', 0):,} | | " +
                     " | ".join(f"{ref['times'].get(k, float('nan')):.3f}" for k, _ in ROWS) + " | |")
    for name, (tris, secs) in PAPER.items():
        lines.append(f"| paper: {name} | {tris:,} | | | " + " | ".join(f"{s:.3f}" for s in secs) + " | |")
    cpu = ""
    try:
        cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")][0]
    except Exception:
        pass
    text = (f"Median of {args.runs} runs, seconds per step (the paper's Table 1 rows); {cpu}, "
            f"{os.cpu_count()} cores, {platform.system()}.\n\n" + "\n".join(lines) + "\n")
    print(text)
    if args.write:
        with open(os.path.join(HERE, "results.md"), "w") as f:
            f.write("# Initial template benchmark\n\nGenerated by `make bench` (bench/run_bench.py).\n\n" + text)


if __name__ == "__main__":
    main()

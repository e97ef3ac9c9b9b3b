#!/usr/bin/env python3
"""Benchmark of the initial template and of the Boolean operation, next to the paper's Table 1.

Runs `surgical-template design` several times per case (the example cases on the real meshes, and
the same meshes refined by midpoint subdivision to about 0.2M, 0.5M and 1M triangles), takes the
median of every step, and prints a Markdown table; --write stores it in bench/results.md.

The Boolean section takes, for every case with drilling tubes, the median of the report's
boolean_operation time over the same runs, and with --reference-boolean runs the reference program
(bench/references/boolean_reference.cpp) on the operands the tool wrote (--operands), once per
library, each in its own process with a timeout: CGAL's corefinement, VTK's
vtkBooleanOperationPolyDataFilter and vtkLoopBooleanPolyDataFilter, and the kernel's mesh_boolean on
the same files. --write replaces that section of bench/results.md and keeps the others.

    /usr/bin/python3 bench/run_bench.py --build build [--runs 5] [--write]
        [--reference build-ref/reference-chain] [--reference-boolean build-ref/boolean-reference]
        [--boolean-only]
"""
import argparse
import json
import os
import platform
import re
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import bumpy_sphere

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

# The paper's "Runtime of Boolean operation" (Table 1), seconds, for the cases that have one, keyed
# by the example case that corresponds to it.
PAPER_BOOLEAN = {
    "maxilla-implants": ("oral: 5 tubes, 213k-triangle input", 16.7),
    "vertebra-pedicle": ("vertebra: 2 tubes", 5.0),
}

# Seconds per library and case before boolean-reference starts no further run; its process is
# killed 30 s after that (a VTK filter can run for minutes or take all the memory on some inputs).
BOOLEAN_TIMEOUT = 120

# The reference program's libraries, in table order: (--library value, column label).
BOOLEAN_LIBRARIES = [
    ("kernel", "kernel, same files"),
    ("cgal", "CGAL corefinement"),
    ("vtk-boolean", "VTK BooleanOperation"),
    ("vtk-loop", "VTK LoopBoolean"),
]

# (case file, refinement levels): each level splits every triangle in four.
SCALED = [("tibia-osteotomy.json", 1), ("sacrum-iliosacral.json", 1), ("maxilla-implants.json", 1),
          ("tibia-osteotomy.json", 2), ("sacrum-iliosacral.json", 2)]


# The bumpy sphere at the paper's resolution (bench/bumpy_sphere.py): (quads per cube-face edge, name).
FINE = [(129, "bumpy-sphere-200k"), (289, "bumpy-sphere-1M")]


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


def run_case(tool, case_path, runs, workdir, operands=None):
    """`runs` designs of the case; with `operands` (a folder) the first run also writes the Boolean
    operands there."""
    reports = []
    commands = []  # the command from its start to its exit (the tool's start-up and exit included)
    for i in range(runs):
        out = os.path.join(workdir, "t.stl")
        rep = os.path.join(workdir, "r.json")
        cmd = [tool, "design", case_path, "-o", out, "--report", rep]
        if operands and i == 0:
            cmd += ["--operands", operands]
        start = time.perf_counter()
        p = subprocess.run(cmd, capture_output=True, text=True)
        commands.append(time.perf_counter() - start)
        if p.returncode != 0:
            return None, p.stderr.strip()
        reports.append(json.load(open(rep)))
    med = {k: statistics.median(r["times"][k] for r in reports) for k, _ in ROWS}
    all_times = {k: statistics.median(r["times"].get(k, 0.0) for r in reports) for k in reports[0]["times"]}
    return {"times": med, "all_times": all_times, "report": reports[0],
            "boolean": statistics.median(r["times"].get("boolean_operation", 0.0) for r in reports),
            "boolean_runs": [r["times"].get("boolean_operation", 0.0) for r in reports],
            "peak_mb": statistics.median(r["peak_memory_mb"] for r in reports),
            "command": statistics.median(commands)}, None


def stl_triangles(path):
    """Triangles of a binary STL, from its size."""
    return (os.path.getsize(path) - 84) // 50


def run_boolean_reference(program, operands, library, runs, timeout, out_stl):
    """One library on one case's operands in its own process. Returns the JSON report, or a dict
    with "failed" when the process crashed, timed out or gave no report (from its progress on
    stderr: which step, the VTK messages before it)."""
    cmd = [program, operands, "--library", library, "--repeat", str(runs), "--budget", str(timeout),
           "--out", out_stl]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout + 30)
        stdout, stderr, code, timed_out = p.stdout, p.stderr, p.returncode, False
    except subprocess.TimeoutExpired as e:
        def text(b):
            return b.decode(errors="replace") if isinstance(b, bytes) else (b or "")
        stdout, stderr, code, timed_out = text(e.stdout), text(e.stderr), None, True
    if code == 0:
        try:
            return json.loads(stdout)
        except ValueError:
            return {"failed": "no JSON report: " + (stderr.strip().splitlines() or ["(no output)"])[-1]}
    # Which step was running: the last "  step ..." line not followed by its "  step: N s".
    step, finished = None, {}
    for line in stderr.splitlines():
        if m := re.fullmatch(r"  (union|difference) \.\.\.", line):
            step = m.group(1)
        elif m := re.fullmatch(r"  (union|difference): ([0-9.e+-]+) s", line):
            step, finished[m.group(1)] = None, float(m.group(2))
    if timed_out:
        what = f"no result after {timeout + 30} s (killed)"
    elif code is not None and code < 0:
        what = f"crashed ({signal.Signals(-code).name})"
    else:
        what = f"exit code {code}: " + (stderr.strip().splitlines() or ["(no output)"])[-1]
    messages = re.findall(r"^  vtk (?:warning|error): (.*)$", stderr, re.M)
    failed = (f"{step}: " if step else "") + what
    if messages:
        failed += " after VTK's " + "; ".join(f"'{m}'" for m in messages[-2:])
    rep = {"failed": failed, "library": library}
    if "union" in finished and step == "difference":
        rep["failed_run_times"] = {"union": finished["union"]}
    return rep


def solid_short(solid):
    """A few words on a st::check_solid verdict (see boolean_reference.cpp's solid_json)."""
    if not solid:
        return "no result"
    if solid.get("valid"):
        return "valid"
    if "border_edges" not in solid:
        return solid.get("summary", "not valid")
    parts = []
    if solid["border_edges"]:
        parts.append(f"{solid['border_edges']} open edges")
    if solid["nonmanifold_edges"] or solid["nonmanifold_vertices"]:
        parts.append(f"{solid['nonmanifold_edges']}+{solid['nonmanifold_vertices']} non-manifold edges+vertices")
    if solid["misoriented_edges"]:
        parts.append(f"{solid['misoriented_edges']} misoriented edges")
    elif solid["volume"] <= 0:
        parts.append("inside out")
    if solid["degenerate_triangles"]:
        parts.append(f"{solid['degenerate_triangles']} degenerate")
    if solid["self_intersections"]:
        n = solid["self_intersections"]
        parts.append(f"{'>=' if n >= 100 else ''}{n} self-intersecting pairs")
    return "no: " + ", ".join(parts)


def one_line(message):
    """A failure message fit for a table cell: one line, VTK's information dumps left out."""
    message = re.sub(r"\(Algorithm vtk.*", "(VTK: algorithm returned failure)", message, flags=re.S)
    return " ".join(message.split()).replace("|", "/")


def boolean_cell(rep):
    """Main table cell: median total time and whether the result, as an STL holds it, is a valid solid."""
    if rep is None:
        return ""
    if rep.get("failed"):
        part = rep.get("failed_run_times", {}).get("union")
        return "failed: " + one_line(rep["failed"]) + (f" (union took {part:.2f} s)" if part else "")
    t = rep["times"]["total"]
    stl = rep.get("solid_stl") or rep.get("solid")
    verdict = solid_short(stl)
    if not stl.get("valid") and rep.get("solid", {}).get("valid"):
        verdict += " after float32 rounding (valid in double)"
    return f"{t:.3f} s, {verdict}"


def boolean_section(cases, runs, reference_used, timeout):
    """The Markdown of the Boolean section (without its heading)."""
    cpu = ""
    try:
        cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")][0]
    except Exception:
        pass
    libs = BOOLEAN_LIBRARIES if reference_used else []
    head = ["case", "input triangles", "template triangles", "tubes", "kernel (tool report)"] + \
        [label for _, label in libs] + ["paper"]
    lines = ["| " + " | ".join(head) + " |", "|---|" + "---:|" * 3 + "---|" * (len(head) - 4)]
    details = []
    for c in cases:
        k = c["kernel"]
        if k is None:
            lines.append(f"| {c['name']} | failed: {c['error']} |")
            continue
        rep = k["report"]
        kernel_cell = f"{k['boolean']:.3f} s, {'valid' if rep['solid']['valid'] else 'NOT valid'}"
        paper = PAPER_BOOLEAN.get(c["name"])
        row = [c["name"], f"{rep['input']['triangles']:,}", f"{c['body_triangles']:,}",
               str(rep["counts"]["drilling_tubes"]), kernel_cell] + \
            [boolean_cell(c["references"].get(lib)) for lib, _ in libs] + \
            [f"{paper[1]:.1f} s ({paper[0]})" if paper else ""]
        lines.append("| " + " | ".join(row) + " |")
        guide_volume = rep["solid"]["volume"]
        for lib, label in libs:
            r = c["references"].get(lib)
            if not r:
                continue
            if r.get("failed"):
                details.append(f"| {c['name']} | {label} | | | | failed: {one_line(r['failed'])} | | |")
                continue
            t = r["times"]
            raw, stl = r.get("solid", {}), r.get("solid_stl", {})
            dv = 100.0 * (raw.get("volume", 0.0) - guide_volume) / guide_volume if guide_volume else float("nan")
            details.append(f"| {c['name']} | {label} | {t['union']:.3f} | {t['difference']:.3f} | {t['total']:.3f} "
                           f"({r['runs']} runs) | {raw.get('triangles', 0):,} tri., {raw.get('components', 0)} comp.; "
                           f"{solid_short(raw)} | {solid_short(stl)} | {dv:+.3f} % |")
    text = (f"`surgical-template design` on each case with drilling tubes: median of {runs} runs of the report's "
            f"`times.boolean_operation` (the paper's \"Runtime of Boolean operation\": placing the tubes with rays, "
            f"uniting the columns with each other and with the template, uniting the bores and cutting them)")
    if reference_used:
        text += (". Side by side, in the same run, `boolean-reference` (bench/references) computes "
                 "(body u columns) - bores from the operands the tool wrote (`--operands`), with each library in "
                 f"its own process (median of up to {runs} runs; no run is started after about {timeout} s, "
                 "the process is killed 30 s later, and its address space is limited to 8 GiB); its times are "
                 "the two Boolean calls only (no reading, conversion or check). \"kernel, same files\" is the "
                 "kernel's `mesh_boolean` doing just those two calls on the same files")
    text += (f". Machine: {cpu}, {os.cpu_count()} cores, {platform.system()}, shared with other work (times vary "
             "by 10-20 %); the paper's times are from a 2012 laptop (Intel i5-3210M).\n\n"
             "\"valid\" means `st::check_solid` passes: closed (no open edge), 2-manifold (edges and vertices), "
             "consistently and outward oriented, no degenerate triangle and no self-intersecting pair of triangles. "
             "The main table checks each result as its STL file holds it (float32 coordinates, corners at the same "
             "point merged), as the kernel checks its own guide; the details also give the library's mesh as it "
             "returned it (double coordinates, its own point sharing)." +
             (" What is and is not comparable: bench/references/README.md, \"Boolean reference\"."
              if reference_used else "") + "\n\n" + "\n".join(lines) + "\n")
    if details:
        text += ("\nDetails (seconds, medians; volume relative to the kernel's guide):\n\n"
                 "| case | library | union | difference | total | as returned | as STL | volume |\n"
                 "|---|---|---:|---:|---:|---|---|---:|\n" + "\n".join(details) + "\n")
    return text



def write_results(initial_text=None, boolean_text=None):
    """bench/results.md: the initial-template part on top, then "## Boolean operation"; a part given
    replaces the stored one, a part not given is kept."""
    path = os.path.join(HERE, "results.md")
    old = open(path).read() if os.path.exists(path) else ""
    marker = "\n## Boolean operation\n"
    old_initial, _, old_boolean = old.partition(marker)
    initial = ("# Initial template benchmark\n\nGenerated by `make bench` (bench/run_bench.py).\n\n" + initial_text
               if initial_text is not None else old_initial.rstrip("\n") + "\n")
    boolean = boolean_text if boolean_text is not None else old_boolean
    with open(path, "w") as f:
        f.write(initial + (marker + "\n" + boolean.lstrip("\n") if boolean.strip() else ""))


def fine_section(fine, runs):
    """bench/results-fine.md: the whole process on the bumpy sphere, beside the reference chain."""
    cpu = ""
    try:
        cpu = [l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")][0]
    except Exception:
        pass
    head = ["case", "input triangles", "region triangles", "output triangles", "design steps", "Boolean step",
            "validation", "whole process", "reference chain (library time)", "whole / reference",
            "CGAL union + bores", "Boolean / CGAL"]
    lines = ["| " + " | ".join(head) + " |", "|---|" + "---:|" * (len(head) - 1)]
    parts = ["| case | validation (wall) | removal check (own) | stability (own) | insertion analysis (beside the shell) "
             "| the command, start to exit |",
             "|---|---:|---:|---:|---:|---:|"]
    for c in fine:
        k = c["kernel"]
        if k is None:
            lines.append(f"| {c['name']} | failed: {c['error']} |")
            continue
        rep, t = k["report"], k["all_times"]
        ref = c.get("reference")
        ref_time = ref["times"].get("initial_template_generation") if ref else None
        cgal = (c.get("booleans") or {}).get("references", {}).get("cgal")
        cgal_time = cgal["times"]["total"] if cgal and not cgal.get("failed") else None
        # Without block-out (these cases) the insertion analysis runs beside the shell:
        # its own wall time is not on the design's path (the second table gives it).
        before = rep.get("insertion", {}).get("blocked_out", False)
        design = t["initial_template_generation"] + (t.get("insertion_analysis", 0.0) if before else 0.0)
        lines.append(
            f"| {c['name']} | {rep['input']['triangles']:,} | {rep['counts']['triangles_of_inner_surface']:,} | "
            f"{rep['counts']['template_triangles']:,} | {design:.3f} | {t['boolean_operation']:.3f} | "
            f"{t['validation']:.3f} | {t['wall_clock']:.3f} | " +
            (f"{ref_time:.3f} | {t['wall_clock'] / ref_time:.2f} |" if ref_time else "| |") +
            (f" {cgal_time:.3f} | {t['boolean_operation'] / cgal_time:.3f} |" if cgal_time else " | |"))
        parts.append(f"| {c['name']} | {t['validation']:.3f} | {t.get('removal_check', 0.0):.3f} | "
                     f"{t.get('stability', 0.0):.3f} | {t.get('insertion_analysis', 0.0):.3f} | "
                     f"{k['command']:.3f} |")
    return ("# The whole process at fine resolution\n\n"
            "Generated by `make bench` (bench/run_bench.py; `make bench-references` adds the references).\n\n"
            "The case a user meets at the paper's resolution: a bumpy sphere (bench/bumpy_sphere.py: 25 mm radius, "
            "bumps 13 mm apart and up to 2 mm high) of 200k triangles, and the same surface at 1M; the region is "
            "the cap within 42 degrees of the pole, T 2.5 mm, h 0.25 mm, five sleeves. "
            f"Median of {runs} runs of `surgical-template design CASE -o OUT.stl --report R.json`, seconds: "
            "\"whole process\" is the report's wall clock from reading the case to the written STL and report "
            "(design, Boolean, validation, insertion, removal and stability analyses included); \"design steps\" "
            "the paper's five steps (the insertion analysis runs beside them, its own wall time in the "
            "second table; with block-out it would run before them and count here); \"validation\" the wall time of the exact solid "
            "check of the guide with the fit, the removal check and the stability, which run beside it on "
            "threads of their own (their own times in the second table overlap it). "
            "The command's time, in the second table, is `surgical-template design` from its start to its exit, as a "
            "shell times it: the whole process with the tool's start-up and exit. The reference chain "
            "(bench/references: VTK select + OpenVDB offset + VTK outer cut + the kernel's ruled wall) is "
            "library time only, no reading, validation or writing; CGAL's time is its union and difference of "
            "the same operands (bench/results.md, \"Boolean operation\"). "
            f"Machine: {cpu}, {os.cpu_count()} cores, {platform.system()}.\n\n" + "\n".join(lines) +
            "\n\nValidation and the analyses beside it, seconds:\n\n" + "\n".join(parts) + "\n")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--build", default=os.path.join(ROOT, "build"))
    ap.add_argument("--runs", type=int, default=5)
    ap.add_argument("--write", action="store_true")
    ap.add_argument("--no-scaled", action="store_true")
    ap.add_argument("--reference", help="path of reference-chain (VTK + OpenVDB) to run side by side")
    ap.add_argument("--reference-boolean",
                    help="path of boolean-reference (CGAL, VTK) to run on the Boolean operands side by side")
    ap.add_argument("--boolean-only", action="store_true",
                    help="only the cases with drilling tubes and only the Boolean section")
    ap.add_argument("--boolean-timeout", type=int, default=BOOLEAN_TIMEOUT,
                    help="seconds per library and case before its runs stop (its process is killed 30 s later)")
    ap.add_argument("--no-fine", action="store_true", help="leave out the bumpy-sphere cases (results-fine.md)")
    ap.add_argument("--fine-only", action="store_true",
                    help="only the bumpy-sphere cases; --write then writes results-fine.md only")
    args = ap.parse_args()
    global BUILD
    BUILD = args.build
    tool = os.path.join(args.build, "surgical-template")
    results = []
    references = []
    booleans = []
    fine = []
    with tempfile.TemporaryDirectory() as work:
        cases = [] if args.fine_only else [(name[:-5], os.path.join(CASES, name))
                                           for name in sorted(os.listdir(CASES)) if name.endswith(".json")]
        if not args.no_fine:
            for n, label in FINE:
                path, triangles = bumpy_sphere.write_case(work, n, label)
                cases.append((label, path))
        for label, case_path in cases:
            name = label + ".json"
            has_tubes = bool(json.load(open(case_path)).get("tubes"))
            if args.boolean_only and not has_tubes:
                continue
            operands = os.path.join(work, name[:-5] + "-operands") if has_tubes else None
            r, err = run_case(tool, case_path, args.runs, work, operands)
            results.append((name[:-5], r, err))
            print(name, "done" if r else err, file=sys.stderr)
            ref = None
            if args.reference and not args.boolean_only:
                ref, ref_err = run_reference(args.reference, case_path, args.runs, work)
                references.append((name[:-5], ref, ref_err))
            if label.startswith("bumpy"):
                fine.append({"name": label, "kernel": r, "error": err, "reference": ref, "booleans": None})
            if has_tubes:
                c = {"name": name[:-5], "kernel": r, "error": err, "references": {},
                     "body_triangles": stl_triangles(os.path.join(operands, "body.stl")) if r else 0}
                if r and args.reference_boolean:
                    for lib, _ in BOOLEAN_LIBRARIES:
                        print(f"  {name[:-5]}: boolean-reference --library {lib}", file=sys.stderr)
                        c["references"][lib] = run_boolean_reference(
                            args.reference_boolean, operands, lib, args.runs, args.boolean_timeout,
                            os.path.join(work, f"{name[:-5]}-{lib}.stl"))
                        rep = c["references"][lib]
                        print("    " + (f"failed: {rep['failed']}" if rep.get("failed") else boolean_cell(rep)),
                              file=sys.stderr)
                booleans.append(c)
                if fine and fine[-1]["name"] == label:
                    fine[-1]["booleans"] = c
        if not args.no_scaled and not args.boolean_only and not args.fine_only:
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

    initial_text = None
    if not args.boolean_only:
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
        initial_text = (f"Median of {args.runs} runs, seconds per step (the paper's Table 1 rows); {cpu}, "
                        f"{os.cpu_count()} cores, {platform.system()}.\n\n" + "\n".join(lines) + "\n")
        print(initial_text)
    boolean_text = boolean_section(booleans, args.runs, bool(args.reference_boolean), args.boolean_timeout)
    print("## Boolean operation\n\n" + boolean_text)
    fine_text = fine_section(fine, args.runs) if fine else None
    if fine_text:
        print(fine_text)
    if args.write:
        if not args.fine_only:
            write_results(initial_text, boolean_text)
        if fine_text and (args.reference or not os.path.exists(os.path.join(HERE, "results-fine.md"))):
            with open(os.path.join(HERE, "results-fine.md"), "w") as f:
                f.write(fine_text)


if __name__ == "__main__":
    main()

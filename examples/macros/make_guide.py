"""A surgical case end to end with the workbench's API: the parametric guide from a case file (or a plan on
a bone), its STL, the FreeCAD document and the documentation drawing (PDF, SVG, drill protocol).

In FreeCAD (Macro > Macros... > Execute) with the workbench installed (`make install`), or headless:

    ST_CASE=examples/cases/sacrum-iliosacral.json ST_OUT=out/sacrum /usr/bin/python3 examples/macros/make_guide.py

Environment: ST_CASE (a case file; default the maxilla implant case), ST_OUT (output folder, default
out/<case name>), ST_PLAN and ST_PRESET (optional: a 3D Slicer markups or CSV plan put on the case's
bone instead of its own boundary and tubes, sizes from the sleeve preset), ST_DRAWING=0 to skip the
drawing (it needs FreeCAD's GUI; headless it runs one under Xvfb).
"""
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")  # for /usr/bin/python3; FreeCAD itself has it
import FreeCAD as App  # noqa: E402

import SurgicalTemplate as st  # noqa: E402  (the workbench: `make install`)

HERE = os.path.dirname(os.path.abspath(__file__))
case_path = os.environ.get("ST_CASE", os.path.join(HERE, "..", "cases", "maxilla-implants.json"))


def main():
    guide = st.load_case(case_path)
    plan = os.environ.get("ST_PLAN")
    if plan:  # the plan replaces the case's boundary (if it has one) and adds its axes as tubes
        old, guide.Tubes = guide.Tubes, []
        for tube in old:
            guide.Document.removeObject(tube.Name)
        guide = st.load_plan(plan, guide, preset=os.environ.get("ST_PRESET") or None)
    doc = guide.Document
    out = os.path.abspath(os.environ.get("ST_OUT", os.path.join("out", guide.Label)))
    os.makedirs(out, exist_ok=True)
    report = st.inspect(guide, show=False)
    App.Console.PrintMessage(f"{guide.Label}: {report['summary']}\n")
    if not report["passed"]:
        raise RuntimeError(f"{guide.Label}: the guide failed its inspection: {report['summary']}")
    written = [st.export(guide, os.path.join(out, guide.Label + ".stl"))]
    fcstd = os.path.join(out, guide.Label + ".FCStd")
    doc.saveAs(fcstd)
    written.append(fcstd)
    if os.environ.get("ST_DRAWING", "1") != "0":
        drawing = st.make_drawing(guide, os.path.join(out, guide.Label + "-drawing.pdf"))
        written += [drawing[k] for k in ("pdf", "svg", "protocol") if drawing.get(k)]
    for path in written:
        App.Console.PrintMessage(f"  wrote {path}\n")
        print(f"wrote {path}")
    return guide


main()

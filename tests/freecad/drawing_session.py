"""Runs inside FreeCAD's Python without its GUI (see test_drawing.py): a guide from a case file, its
documentation drawing made headless (so the PDF and SVG come from FreeCAD's GUI in a subprocess under
Xvfb), and what the test asserts. Prints one JSON line "RESULT {...}"."""
import json
import os
import sys
import time

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App  # noqa: E402

import SurgicalTemplate as st  # noqa: E402  (found in the Mod folder FreeCAD scanned)

case, out = os.environ["ST_CASE"], os.environ["ST_OUT"]
result = {"gui_up": bool(App.GuiUp)}

guide = st.load_case(case)
doc = guide.Document
doc.UndoMode = 1
result["case"] = guide.Label
box = guide.Mesh.BoundBox
result["guide_box"] = [box.XMin, box.YMin, box.ZMin, box.XMax, box.YMax, box.ZMax]
result["tubes"] = [{"name": t.Label, "offset": t.Offset.Value, "length": t.Length.Value,
                    "inner_diameter": t.InnerDiameter.Value, "outer_diameter": t.OuterDiameter.Value,
                    "depth": t.Depth.Value}
                   for t in guide.Tubes]

# The title block's data, as a user fills them in.
CASE_DATA = {"CaseId": "MX-2026-0412", "Revision": "C", "Owner": "St. Anna Dental Lab", "Status": "Released",
             "DesignedBy": "A. Designer", "CheckedBy": "B. Checker", "ApprovedBy": "C. Approver",
             "Surgeon": "Dr. D. Surgeon", "ImplantSystem": "Straumann BLT 4.1", "Material": "Dental SG resin",
             "PrintingProcess": "SLA, 50 um layers"}
info = st.set_case_info(guide, **CASE_DATA)
if os.path.basename(case) == "maxilla-implants.json":   # its scan in 3D Slicer's LPS frame, as a user states
    st.set_case_info(guide, PatientFrame="LPS")
try:
    st.set_case_info(guide, PatientFrame="XYZ")
except ValueError as e:
    result["frame_error"] = str(e)
result["case_data"] = CASE_DATA
result["case_info_made_by_load_case"] = info.Label
try:
    st.set_case_info(guide, Colour="red")
except ValueError as e:
    result["case_data_error"] = str(e)

start = time.time()
drawing = st.make_drawing(guide, os.path.join(out, "guide-drawing.pdf"))
result["seconds"] = time.time() - start
page = drawing["page"]
result["files"] = {k: drawing[k] for k in ("pdf", "svg", "protocol_path")}
result["protocol"] = drawing["protocol"]
result["page"] = {"label": page.Label, "template": os.path.basename(page.Template.Template),
                  "state": list(page.State), "title_block": dict(page.Template.EditableTexts)}

views, dims, balloons = [], [], []
for v in page.Views:
    if v.isDerivedFrom("TechDraw::DrawViewBalloon"):
        balloons.append({"view": v.SourceView.Label, "text": v.Text, "at": [v.X.Value, v.Y.Value],
                         "origin": [v.OriginX.Value, v.OriginY.Value], "state": list(v.State)})
    elif v.isDerivedFrom("TechDraw::DrawViewDimension"):
        ref = v.References2D[0]
        dims.append({"view": ref[0].Name, "refs": list(ref[1]), "type": v.Type, "value": v.getRawValue(),
                     "text": v.getText(), "state": list(v.State)})
    elif v.isDerivedFrom("TechDraw::DrawViewPart"):
        views.append({"name": v.Name, "label": v.Label, "sources": [s.Label for s in v.Source],
                      "source_types": [s.TypeId for s in v.Source], "direction": list(v.Direction),
                      "visible_edges": len(v.getVisibleEdges()), "hidden_edges": len(v.getHiddenEdges()),
                      "x": v.X.Value, "y": v.Y.Value, "scale": v.Scale, "state": list(v.State)})
    else:
        views.append({"name": v.Name, "label": v.Label, "type": v.TypeId,
                      "text": list(getattr(v, "Text", [])), "x": v.X.Value, "y": v.Y.Value})
result["views"], result["dimensions"], result["balloons"] = views, dims, balloons
result["sheets"] = {o.Label: [o.getContents(c).lstrip("'") for c in ("A1", "A2", "A3", "B3")]
                    for o in doc.Objects if o.TypeId == "Spreadsheet::Sheet"}

# One undo step removes the drawing; a second drawing replaces the first.
count = len(doc.Objects)
doc.undo()
result["objects_after_undo"] = {"before": count, "after": len(doc.Objects),
                                "pages": len([o for o in doc.Objects if o.TypeId == "TechDraw::DrawPage"])}
doc.redo()
st.make_drawing(guide, os.path.join(out, "again"), pdf=False, svg=False)
result["pages_after_second_drawing"] = len([o for o in doc.Objects if o.TypeId == "TechDraw::DrawPage"])

# A change to the guide marks its drawing out of date; a new drawing is up to date again.
page = [o for o in doc.Objects if o.TypeId == "TechDraw::DrawPage"][0]
fresh = {"out_of_date": page.OutOfDate, "label": page.Label}
guide.Tubes[0].Length = guide.Tubes[0].Length.Value + 0.5
doc.recompute()
result["drawing_after_change"] = {"fresh": fresh, "out_of_date": page.OutOfDate, "label": page.Label}
again = st.make_drawing(guide, os.path.join(out, "again"), pdf=False, svg=False)["page"]
result["drawing_after_change"]["new"] = {"out_of_date": again.OutOfDate, "label": again.Label}

# Clear errors.
class _EmptyGuide:
    """A guide whose mesh stays empty."""
    kind = "Guide"

    def __init__(self, obj, like):
        obj.Proxy = self
        obj.addProperty("App::PropertyLink", "Shell")
        obj.addProperty("App::PropertyLinkList", "Tubes")
        obj.Shell = like.Shell
        obj.Label = "EmptyGuide"

    def execute(self, obj):
        pass


errors = {}
for tag, call in (("paper", lambda: st.make_drawing(guide, os.path.join(out, "x"), paper="B7")),
                  ("not_a_guide", lambda: st.make_drawing(guide.Shell, os.path.join(out, "x"))),
                  ("empty", None)):
    if call is None:
        empty = doc.addObject("Mesh::FeaturePython", "EmptyGuide")
        _EmptyGuide(empty, guide)
        call = (lambda e=empty: st.make_drawing(e, os.path.join(out, "x"), pdf=False, svg=False))
    try:
        call()
        errors[tag] = None
    except (ValueError, RuntimeError) as e:
        errors[tag] = f"{type(e).__name__}: {e}"
result["errors"] = errors
result["leftovers"] = sorted(f for f in os.listdir(out) if f.startswith(".drawing-") or ".tmp" in f)
print("RESULT " + json.dumps(result))

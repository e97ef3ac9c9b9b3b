"""Runs inside FreeCAD's Python (see test_tube_sizes.py): a tube's sizes as diameters driven by a
spreadsheet expression, and a document with the radii and plain vectors of versions before 0.4
migrated on opening. Prints one JSON line "RESULT {...}"."""
import json
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App  # noqa: E402

import SurgicalTemplate as st  # noqa: E402  (found in the Mod folder FreeCAD scanned)
import st_bridge  # noqa: E402

case, out = os.environ["ST_CASE"], os.environ["ST_OUT"]
k = st_bridge.kernel()
result = {}


def state(guide):
    V, F = st_bridge.mesh_to_arrays(guide.Mesh)
    report = k.check_solid(V, F)
    tubes = {t.Label: {"inner": t.InnerDiameter.Value, "outer": t.OuterDiameter.Value,
                       "counterbore": t.CounterboreDiameter.Value, "entry": list(t.Entry),
                       "direction": list(t.Direction), "types": [t.getTypeIdOfProperty(p) for p in ("Entry", "Direction")],
                       "expressions": {p.lstrip("."): e for p, e in t.ExpressionEngine},
                       "radius_properties": [p for p in t.PropertiesList if p.endswith("Radius")]}
             for t in guide.Tubes}
    return {"valid": report["valid"], "volume": report["volume"], "tubes": tubes, "state": list(guide.State)}


guide = st.load_case(case)
doc = guide.Document
result["loaded"] = state(guide)
result["spec"] = {t.Label: t.Proxy.spec(t) for t in guide.Tubes}
for spec in result["spec"].values():
    for key in ("entry", "direction"):
        spec[key] = list(spec[key])

# The outer diameter of the first tube from a spreadsheet cell, as a user types "=Spreadsheet.D".
sheet = doc.addObject("Spreadsheet::Sheet", "Spreadsheet")
sheet.set("A1", "6.4 mm")
sheet.setAlias("A1", "D")
doc.recompute()
tube = guide.Tubes[1]
tube.setExpression("OuterDiameter", "Spreadsheet.D")
doc.recompute()
result["driven"] = state(guide)
sheet.set("A1", "7 mm")
doc.recompute()
result["driven_wider"] = state(guide)

# The same document as a version before 0.4 saved it: radii (an expression on one) and plain vectors.
for t in guide.Tubes:
    expressions = {p.lstrip("."): e for p, e in t.ExpressionEngine}
    for new, old in (("InnerDiameter", "InnerRadius"), ("OuterDiameter", "OuterRadius"),
                     ("CounterboreDiameter", "CounterboreRadius")):
        value = getattr(t, new).Value / 2.0
        if new in expressions:
            t.setExpression(new, None)
        t.removeProperty(new)
        t.addProperty("App::PropertyLength", old, "Tube", "radius")
        setattr(t, old, value)
        if new in expressions:
            t.setExpression(old, expressions[new] + " / 2")
    for name in ("Entry", "Direction"):
        value = App.Vector(getattr(t, name))
        t.removeProperty(name)
        t.addProperty("App::PropertyVector", name, "Tube", "vector")
        setattr(t, name, value)
result["old_layout"] = {t.Label: sorted(p for p in t.PropertiesList if p.endswith(("Radius", "Diameter")))
                        for t in guide.Tubes}
path = os.path.join(out, "before-0.4.FCStd")
doc.saveAs(path)
App.closeDocument(doc.Name)

doc = App.openDocument(path)
guide = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Guide"][0]
result["reopened"] = state(guide)
doc.recompute()
result["recomputed"] = state(guide)
doc.getObject("Spreadsheet").set("A1", "6.4 mm")
doc.recompute()
result["reopened_driven"] = state(guide)
print("RESULT " + json.dumps(result))

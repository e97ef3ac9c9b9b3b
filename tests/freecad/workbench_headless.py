"""Runs inside FreeCAD's Python (see test_workbench.py): the workbench API end to end, headless.
Prints one JSON line "RESULT {...}" with what the test asserts."""
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


def measure(guide, tag):
    path = os.path.join(out, tag + ".stl")
    st.export(guide, path)
    report = k.check_solid(*k.read_mesh(path))
    result[tag] = {"valid": report["valid"], "components": report["components"], "volume": report["volume"],
                   "facets": guide.Mesh.CountFacets, "state": list(guide.State)}


guide = st.load_case(case)
doc = guide.Document
doc.UndoMode = 1
measure(guide, "loaded")
result["tree"] = {"shell": guide.Shell.Name, "tubes": [t.Label for t in guide.Tubes],
                  "thickness": guide.Shell.Thickness.Value, "outer_radius": guide.Tubes[0].OuterDiameter.Value / 2,
                  "tube_is_solid": guide.Tubes[0].Shape.isValid() and len(guide.Tubes[0].Shape.Solids) == 1,
                  "tube_volume": guide.Tubes[0].Shape.Volume}

guide.Tubes[0].OuterDiameter = guide.Tubes[0].OuterDiameter.Value + 1.6
doc.recompute()
measure(guide, "wider_sleeve")
guide.Shell.Thickness = guide.Shell.Thickness.Value + 1.0
doc.recompute()
measure(guide, "thicker")

# Undo and redo of one parameter change.
doc.openTransaction("thinner")
guide.Shell.Thickness = 2.0
doc.commitTransaction()
doc.recompute()
measure(guide, "thinner")
doc.undo()
doc.recompute()
result["after_undo_thickness"] = guide.Shell.Thickness.Value
measure(guide, "undone")
doc.redo()
doc.recompute()
result["after_redo_thickness"] = guide.Shell.Thickness.Value
doc.undo()
doc.recompute()

# A failing kernel call leaves the document usable and the last good guide in place.
tube = guide.Tubes[0]
entry = App.Vector(tube.Entry)
tube.Entry = entry + App.Vector(200, 200, 200)
doc.recompute()
result["failed"] = {"state": list(guide.State), "facets": guide.Mesh.CountFacets}
tube.Entry = entry
doc.recompute()
measure(guide, "repaired")

# Save, close, reopen, recompute: the same guide.
fcstd = os.path.join(out, "guide.FCStd")
doc.saveAs(fcstd)
name = guide.Name
App.closeDocument(doc.Name)
doc = App.openDocument(fcstd)
guide = doc.getObject(name)
result["restored_facets"] = guide.Mesh.CountFacets
for o in doc.Objects:
    o.touch()
doc.recompute()
measure(guide, "reopened")

# Case round trip.
saved = st.save_case(guide, os.path.join(out, "roundtrip.json"))
again = st.load_case(saved)
measure(again, "roundtrip")
result["roundtrip_case"] = json.load(open(saved))
result["insertion"] = {"loaded": guide.Shell.Insertion, "roundtrip": again.Shell.Insertion,
                       "undercut": again.Shell.UndercutArea.Value}
# A template asked for the least-undercut direction reports its undercut, and a case saved from it
# says "auto".
again.Shell.Insertion = "Auto"
again.Document.recompute()
auto_case = json.load(open(st.save_case(again, os.path.join(out, "auto.json"))))
result["insertion"]["auto_case"] = auto_case["template"].get("insertion")
result["insertion"]["auto_status"] = again.Shell.Status
result["insertion"]["auto_undercut"] = again.Shell.UndercutArea.Value
result["insertion"]["auto_removable"] = again.Shell.Removable
result["insertion"]["auto_used"] = list(again.Shell.InsertionUsed)
# Validate's inspection checks the finished guide comes off along that direction.
inspected = st.inspect(again)
removal = inspected["removal"]
result["insertion"]["inspect_removable"] = removal["removable"] if removal else None
# The stability score: on the template from its design, on the guide for expressions, and Validate's own.
result["insertion"]["stability"] = {"template": again.Shell.StabilityScore, "guide": again.StabilityScore,
                                    "inspect": inspected["stability"]["score"] if inspected["stability"] else None,
                                    "contacts": inspected["stability"]["contacts"] if inspected["stability"] else 0}
# A direction set by the API (as "Insertion from view" does) is the one used.
st.set_insertion(again.Shell, (0, 0, -2))
again.Document.recompute()
result["insertion"]["set_mode"] = again.Shell.Insertion
result["insertion"]["set_used"] = list(again.Shell.InsertionUsed)
# The tibia cutting guide: its pins load as tubes (one planned without a direction gets the kernel's,
# the screw keeps its counterbore), its saw slots are cut in the guide, and a case saved from it keeps
# both.
tibia = json.load(open(os.path.join(os.path.dirname(case), "tibia-osteotomy.json")))
tibia["bone"] = os.path.join(os.path.dirname(case), tibia["bone"])
del tibia["tubes"][0]["direction"]
tibia.pop("output", None)
tibia_path = os.path.join(out, "tibia.json")
json.dump(tibia, open(tibia_path, "w"))
pinned = st.load_case(tibia_path)
measure(pinned, "tibia")
bv, bf = k.read_mesh(tibia["bone"])
saved_tibia = json.load(open(st.save_case(pinned, os.path.join(out, "tibia-saved.json"))))
result["tibia_tree"] = {"tubes": [t.Label for t in pinned.Tubes], "kinds": [t.Kind for t in pinned.Tubes],
                        "counterbore": [pinned.Tubes[1].CounterboreDiameter.Value / 2, pinned.Tubes[1].CounterboreDepth.Value],
                        "direction": [list(t.Direction) for t in pinned.Tubes],
                        "kernel_direction": list(k.pin_direction(bv, bf, tibia["tubes"][0]["entry"],
                                                                 tibia["tubes"][0]["outer_radius"])),
                        "slots": [s["name"] for s in st.slots_of(pinned)],
                        "part_objects": [[p.Proxy.kind, p.Label, p.TypeId, p.Shape.isValid()] for p in pinned.Parts],
                        "saved_slots": [s["name"] for s in saved_tibia.get("slots", [])],
                        "saved_kinds": [t.get("kind", "sleeve") for t in saved_tibia["tubes"]],
                        "saved_counterbore": saved_tibia["tubes"][1].get("counterbore"),
                        "labels": [l["text"] for l in st.labels_of(pinned)],
                        "saved_labels": [l["text"] for l in saved_tibia.get("labels", [])]}
# The same guide without its slots has more material: the slots are cut.
parts = list(pinned.Parts)
# A slot's blade from the catalogue: its BladePreset sets thickness and clearance (then set back).
slot_object = [p for p in parts if p.Proxy.kind == "Slot"][0]
before = (slot_object.BladePreset, slot_object.Blade.Value, slot_object.Clearance.Value)
choices = slot_object.getEnumerationsOfProperty("BladePreset")
thickness = {b["name"]: b["thickness"] for b in st.blade_presets()}
choice = [c for c in choices[1:] if abs(thickness[c] - before[1]) > 1e-6][0]
slot_object.BladePreset = choice
result["blade_choice"] = {"choices": choices, "before": before, "name": choice, "blade": slot_object.Blade.Value,
                          "clearance": slot_object.Clearance.Value,
                          "catalogue": [b for b in st.blade_presets() if b["name"] == choice][0]}
slot_object.BladePreset, slot_object.Blade, slot_object.Clearance = before
pinned.Parts = [p for p in parts if p.Proxy.kind != "Slot"]
doc_tibia = pinned.Document
doc_tibia.recompute()
measure(pinned, "tibia_without_slots")
pinned.Parts = parts
doc_tibia.recompute()
result["tibia_protocol"] = st.drill_protocol(pinned)
# Validate's slot and label rows: each blade path checked on the finished mesh; a chip of material left in
# a slot (a 0.2 mm cube in the middle of its cut) fails the guide, naming the slot.
checked = st.inspect(pinned, show=False)
result["tibia_parts"] = {"rows": checked["parts"], "passed": checked["passed"]}
import Mesh  # noqa: E402
laid, planned = json.loads(pinned.PartsReport)["slots"][0], st.slots_of(pinned)[0]
z = 0.5 * (laid["cut"][0] + laid["housing"][1])
chip_at = [o - z * d for o, d in zip(planned["origin"], laid["direction"])]
chipped = pinned.Mesh.copy()
corner = [[chip_at[i] + (0.1 if (k >> i) & 1 else -0.1) for i in range(3)] for k in range(8)]
quads = [(0, 2, 3, 1), (4, 5, 7, 6), (0, 1, 5, 4), (2, 6, 7, 3), (0, 4, 6, 2), (1, 3, 7, 5)]
chipped.addMesh(Mesh.Mesh([[corner[q[0]], corner[q[i]], corner[q[i + 1]]] for q in quads for i in (1, 2)]))
pinned.Mesh = chipped
blocked = st.inspect(pinned, show=False)
result["tibia_parts"]["chipped"] = {"passed": blocked["passed"], "summary": blocked["summary"],
                                    "rows": blocked["parts"]}
pinned.touch()
pinned.Document.recompute()
# And without its label: the engraving takes material too.
pinned.Parts = [p for p in parts if p.Proxy.kind != "Label"]
doc_tibia.recompute()
measure(pinned, "tibia_without_labels")
pinned.Parts = parts
doc_tibia.recompute()
# Labels and slots added through the API: one undo step each; a refused one leaves the guide as it was.
volume_before = pinned.Mesh.Volume
added = {}
doc_tibia.UndoMode = 1
pinned.Parts = [p for p in parts if p.Proxy.kind != "Label"]
pinned.Label = "TIB 1"   # the case's name, the default text (the example's is too long for this guide)
doc_tibia.recompute()
label = st.add_label(pinned, (621.0, 412.0, 350.0), (0, 0, 1), height=3.5)
added["label"] = {"text": label["text"], "name": label["name"], "count": len(st.labels_of(pinned)),
                  "state": list(pinned.State), "volume": pinned.Mesh.Volume}
try:
    st.add_label(pinned, (621.0, 412.0, 359.0), (0, 0, 1), text="NEAR")
    added["refused"] = None
except RuntimeError as e:
    added["refused"] = str(e)
added["after_refusal"] = {"count": len(st.labels_of(pinned)), "objects": len(doc_tibia.Objects), "state": list(pinned.State),
                          "volume": pinned.Mesh.Volume}
slot = st.add_slot(pinned, (617.0, 411.9, 369.0), (0, 0, 1), (0, 1, 0), blade=0.6, length=12, closed=["start"])
added["slot"] = {"name": slot["name"], "count": len(st.slots_of(pinned)), "state": list(pinned.State)}
doc_tibia.undo()
doc_tibia.recompute()
added["after_undo"] = {"slots": len(st.slots_of(pinned)), "labels": len(st.labels_of(pinned))}
result["added"] = added
print("RESULT " + json.dumps(result))

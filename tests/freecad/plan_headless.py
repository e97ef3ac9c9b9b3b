"""Runs inside FreeCAD's Python (see test_plan_import.py): plans imported through the workbench API
onto bones, templates and guides, in LPS and RAS; bad plans leave the document as it was.
Prints one JSON line "RESULT {...}" with what the test asserts."""
import json
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App  # noqa: E402

import SurgicalTemplate as st  # noqa: E402
import st_bridge  # noqa: E402

examples, out = os.environ["ST_EXAMPLES_DIR"], os.environ["ST_OUT"]
k = st_bridge.kernel()
result = {}


def drop_slots(guide):
    """Removes the guide's Slot objects from it and from the document."""
    for p in [p for p in guide.Parts if p.Proxy.kind == "Slot"]:
        guide.Parts = [q for q in guide.Parts if q != p]
        guide.Document.removeObject(p.Name)


def solid(obj, tag):
    path = os.path.join(out, tag + ".stl")
    st.export(obj, path)
    r = k.check_solid(*k.read_mesh(path))
    return {"valid": r["valid"], "components": r["components"], "volume": r["volume"]}


def attempt(tag, call, doc):
    """Runs a call that must fail; records the message and whether the document stayed as it was."""
    before = sorted(o.Name for o in doc.Objects)
    try:
        call()
        result[tag] = {"raised": False}
    except (ValueError, RuntimeError) as e:
        result[tag] = {"raised": True, "message": str(e), "unchanged": sorted(o.Name for o in doc.Objects) == before}


vertebra = k.read_case(os.path.join(examples, "cases", "vertebra-pedicle.json"))
plan_path = os.path.join(examples, "plans", "vertebra-plan.mrk.json")

# 1. A Slicer plan (RAS markups) on a bare bone saved in LPS: boundary, template, guide with two tubes.
doc = App.newDocument("PlanOnBone")
doc.UndoMode = 1
bone = st.make_bone(vertebra["bone"], doc)
attempt("no_sizes", lambda: st.load_plan(plan_path, bone), doc)
guide = st.load_plan(plan_path, bone, preset="drill-2.5")
preset = [p for p in st.sleeve_presets() if p["name"] == "drill-2.5"][0]
boundary = guide.Shell.Boundary
result["on_bone"] = {
    "solid": solid(guide, "on-bone"),
    "space": bone.CoordinateSystem,
    "tubes": [t.Label for t in guide.Tubes],
    "depths": [t.Depth.Value for t in guide.Tubes],
    "inner_radii": [t.InnerDiameter.Value / 2 for t in guide.Tubes],
    "preset_inner_radius": preset["inner_radius"],
    "point_error": max((p - App.Vector(*q)).Length for p, q in zip(boundary.Points, vertebra["boundary_points"])),
    "inside_error": (boundary.Inside - App.Vector(*vertebra["inside"])).Length,
    "objects": len(doc.Objects),
}
doc.undo()  # the whole import is one step
result["on_bone"]["after_undo"] = sorted(o.Name for o in doc.Objects)

# 2. The same bone saved by Slicer in RAS (mirrored, "SPACE=RAS" in its header): the plan lands mirrored.
V, F = k.read_mesh(vertebra["bone"])
V[:, :2] *= -1
ras_path = os.path.join(out, "vertebra-ras.stl")
k.write_stl(V, F, ras_path, "3D Slicer output. SPACE=RAS")
ras_doc = App.newDocument("PlanOnRasBone")
ras_bone = st.make_bone(ras_path, ras_doc)
ras_guide = st.load_plan(plan_path, ras_bone, preset="drill-2.5")
mirror = lambda p: App.Vector(-p[0], -p[1], p[2])  # noqa: E731
result["on_ras_bone"] = {
    "space": ras_bone.CoordinateSystem,
    "solid": solid(ras_guide, "on-ras-bone"),
    "point_error": max((p - mirror(q)).Length
                       for p, q in zip(ras_guide.Shell.Boundary.Points, vertebra["boundary_points"])),
    "entry_error": (ras_guide.Tubes[0].Entry - mirror(vertebra["tubes"][0]["entry"])).Length,
}

# 3. A CSV of the maxilla's implant axes onto a template: the same guide as the case file's.
maxilla_case = os.path.join(examples, "cases", "maxilla-implants.json")
from_case = st.load_case(maxilla_case)
reference = solid(from_case, "maxilla-case")
csv_doc = App.newDocument("CsvOnTemplate")
m = k.read_case(maxilla_case)
m_bone = st.make_bone(m["bone"], csv_doc)
shell = st.make_template(st.make_boundary(m_bone, m["boundary_points"], m["inside"]), m["thickness"], m["clearance"],
                         m["resolution"] or 0.0)
csv_doc.recompute()
csv_guide = st.load_plan(os.path.join(examples, "plans", "maxilla-implants.csv"), m_bone)  # finds the template
result["csv"] = {"solid": solid(csv_guide, "maxilla-csv"), "reference": reference,
                 "tubes": [t.Label for t in csv_guide.Tubes], "depths": [t.Depth.Value for t in csv_guide.Tubes],
                 "on_the_template": csv_guide.Shell == shell,
                 "boundaries": len([o for o in csv_doc.Objects if getattr(getattr(o, "Proxy", None), "kind", "") ==
                                    "Boundary"])}

# 4. Bad plans name the file and the entry and change nothing.
bad_csv = os.path.join(out, "bad.csv")
with open(bad_csv, "w") as f:
    f.write("name,entry_x,entry_y,entry_z,direction_x,direction_y,direction_z\nA,1,2,3,0,0,1\nB,1,oops,3,0,0,1\n")
attempt("bad_csv", lambda: st.load_plan(bad_csv, csv_guide), csv_doc)
bad_json = os.path.join(out, "bad.mrk.json")
with open(bad_json, "w") as f:
    f.write('{"markups": [{"type": "Line", "controlPoints": [{"position": [0, 0, 0]}]}]}')
attempt("bad_markups", lambda: st.load_plan(bad_json, csv_guide), csv_doc)
attempt("bad_preset", lambda: st.load_plan(plan_path, csv_guide, preset="no-such-sleeve"), csv_doc)

# A step that fails leaves nothing behind, also where the document keeps no undo (freecadcmd's default).
plain = App.newDocument("NoUndo")
plain.UndoMode = 0
try:
    with st._Step(plain, "failing"):
        st.make_tube((0, 0, 0), (0, 0, -1), 1, 2, 5, doc=plain)
        raise RuntimeError("fails after making a tube")
except RuntimeError:
    pass
result["failed_step_objects"] = [o.Name for o in plain.Objects]

# 5. A case with Slicer markups round-trips through the document: import, save, import: equal.
slicer_case = os.path.join(examples, "cases", "vertebra-pedicle-slicer.json")
g = st.load_case(slicer_case)
saved = os.path.join(out, "roundtrip.json")
st.save_case(g, saved)
a, b = k.read_case(slicer_case), k.read_case(saved)
result["roundtrip"] = {
    "points": float(abs(a["boundary_points"] - b["boundary_points"]).max()),
    "tubes": [[t["name"], float(abs(t["entry"] - u["entry"]).max()), float(abs(t["direction"] - u["direction"]).max()),
               t["depth"], u["depth"], t["inner_radius"] == u["inner_radius"], t["length"] == u["length"]]
              for t, u in zip(a["tubes"], b["tubes"])],
}
g2 = st.load_case(saved)
result["roundtrip"]["volumes"] = [solid(g, "rt-a")["volume"], solid(g2, "rt-b")["volume"]]

# 6. The user's own sleeve catalogue extends the project's.
mine = st.user_presets_path()
os.makedirs(os.path.dirname(mine), exist_ok=True)
with open(mine, "w") as f:
    json.dump({"format": "surgical-template-sleeves/1", "sleeves": [
        {"name": "my-sleeve", "inner_diameter": 2.0, "outer_diameter": 5.0, "length": 7},
        {"name": "pilot-2.0", "inner_diameter": 2.2, "outer_diameter": 4.2, "length": 6}]}, f)
presets = {p["name"]: p for p in st.sleeve_presets()}
result["presets"] = {"names": sorted(presets), "mine": presets["my-sleeve"], "replaced": presets["pilot-2.0"]}
tube = st.make_tube((0, 0, 0), (0, 0, -1), preset="my-sleeve", doc=csv_doc, name="T")
result["presets"]["tube"] = [tube.InnerDiameter.Value / 2, tube.OuterDiameter.Value / 2, tube.Length.Value, tube.Offset.Value,
                             tube.Preset]
os.remove(mine)

# 7. 3D Slicer cut planes onto a cutting guide: slots whose saw travels into the bone, blade and length chosen.
flap = st.load_case(os.path.join(examples, "cases", "tibia-segment-flap.json"))
drop_slots(flap)
flap.Document.recompute()
planes_path = os.path.join(examples, "plans", "tibia-flap-planes.mrk.json")
attempt("no_blade", lambda: st.load_plan(planes_path, flap, slot_length=14), flap.Document)
flap = st.load_plan(planes_path, flap, blade="sagittal-0.89", slot_length=14)
attempt("taken", lambda: st.load_plan(planes_path, flap, blade=1.0, slot_length=14), flap.Document)
slots = st.slots_of(flap)
saved = os.path.join(out, "flap-planes.json")
st.save_case(flap, saved)
result["planes"] = {"solid": solid(flap, "flap-planes"), "status": flap.Status,
                    "slots": [[sl["name"], sl.get("direction"), sl["blade"], sl["clearance"], sl["length"]] for sl in slots],
                    "saved": [[sl["name"], sl["direction"]] for sl in k.read_case(saved)["slots"]]}

print("RESULT " + json.dumps(result))

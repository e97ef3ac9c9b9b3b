"""Runs inside FreeCAD's Python (see test_native.py): a guide made without the GUI, saved as a document
for the GUI to open; written for printing in each format and its sleeves as STEP; a case and a plan
read through the File > Open / Import module. Prints one JSON line "RESULT {...}"."""
import json
import os
import sys
import zipfile
import xml.etree.ElementTree as ET

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App  # noqa: E402
import Part  # noqa: E402

import SurgicalTemplate as st  # noqa: E402
import st_bridge  # noqa: E402
import st_import  # noqa: E402

examples, out = os.environ["ST_EXAMPLES_DIR"], os.environ["ST_OUT"]
k = st_bridge.kernel()
result = {}


def drop_slots(guide):
    """Removes the guide's Slot objects from it and from the document."""
    for p in [p for p in guide.Parts if p.Proxy.kind == "Slot"]:
        guide.Parts = [q for q in guide.Parts if q != p]
        guide.Document.removeObject(p.Name)


def volume_3mf(path):
    """The volume of the first object of a 3MF file, read by its XML (FreeCAD 0.20 writes 3MF but reads
    none): units and triangles as the file says."""
    with zipfile.ZipFile(path) as z:
        root = ET.fromstring(z.read("3D/3dmodel.model"))
    ns = {"m": root.tag[1:].split("}")[0]}
    mesh = root.find(".//m:mesh", ns)
    V = [[float(v.get(c)) for c in "xyz"] for v in mesh.find("m:vertices", ns)]
    F = [[int(t.get(c)) for c in ("v1", "v2", "v3")] for t in mesh.find("m:triangles", ns)]
    total = 0.0
    for a, b, c in F:
        (ax, ay, az), (bx, by, bz), (cx, cy, cz) = V[a], V[b], V[c]
        total += ax * (by * cz - bz * cy) - ay * (bx * cz - bz * cx) + az * (bx * cy - by * cx)
    return {"unit": root.get("unit"), "volume": total / 6.0, "triangles": len(F)}


guide = st.load_case(os.path.join(examples, "cases", "maxilla-implants.json"))
doc = guide.Document
document = os.path.join(out, "headless.FCStd")
doc.saveAs(document)
result["document"] = document
result["hidden"] = {o.Label: o.Visibility for o in [guide.Shell, *guide.Tubes, guide]}

# For printing: each format written whole, the 3MF in mm with the guide's volume.
files = {}
for ext in ("3mf", "stl", "obj", "step"):
    path = st.export(guide, os.path.join(out, "guide." + ext))
    files[ext] = {"size": os.path.getsize(path)}
files["3mf"].update(volume_3mf(os.path.join(out, "guide.3mf")))
files["stl"]["volume"] = k.check_solid(*k.read_mesh(os.path.join(out, "guide.stl")))["volume"]
step = Part.read(os.path.join(out, "guide.step"))
files["step"].update({"solids": len(step.Solids), "volume": step.Volume,
                      "tubes": sum(t.Shape.Volume for t in guide.Tubes)})
result["files"] = files
result["guide_volume"] = k.check_solid(*st_bridge.mesh_to_arrays(guide.Mesh))["volume"]  # in double precision
result["leftovers"] = sorted(f for f in os.listdir(out) if ".part" in f)
errors = {}
for tag, call in (("format", lambda: st.export(guide, os.path.join(out, "guide.xyz"))),
                  ("step_of_template", lambda: st.export(guide.Shell, os.path.join(out, "t.step")))):
    try:
        call()
        errors[tag] = None
    except ValueError as e:
        errors[tag] = str(e)
result["export_errors"] = errors

# File > Open of a case builds its tree; File > Import of a plan goes on the document's bone.
opened = st_import.open(os.path.join(examples, "cases", "tibia-segment-flap.json"))
result["opened"] = {"kind": opened.Proxy.kind, "tubes": len(opened.Tubes),
                    "slots": [s["name"] for s in st.slots_of(opened)], "state": list(opened.State)}
drop_slots(opened)
opened.Document.recompute()
st_import.insert(os.path.join(examples, "plans", "tibia-flap-planes.mrk.json"), opened.Document.Name)
result["inserted"] = {"slots": [s["name"] for s in st.slots_of(opened)], "state": list(opened.State)}
try:
    st_import.open(os.path.join(examples, "plans", "vertebra-plan.mrk.json"))
    result["plan_opened_alone"] = None
except ValueError as e:
    result["plan_opened_alone"] = str(e)
result["import_types"] = App.getImportType("json")

print("RESULT " + json.dumps(result))

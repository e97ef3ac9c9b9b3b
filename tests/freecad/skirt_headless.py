"""Runs inside FreeCAD's Python (see test_skirt.py): a template on a sphere FreeCAD's mesher tessellates,
its border drawn 20 degrees beyond the equator and its insertion straight down. Prints one JSON line
"RESULT {...}"."""
import json
import math
import os
import sys

sys.path.append("/usr/lib/freecad-python3/lib")
import FreeCAD as App  # noqa: E402
import MeshPart  # noqa: E402
import Part  # noqa: E402

import SurgicalTemplate as st  # noqa: E402  (found in the Mod folder FreeCAD scanned)
import st_bridge  # noqa: E402

doc = App.newDocument("Skirt")
bone = st.make_bone(MeshPart.meshFromShape(Shape=Part.makeSphere(20.0), MaxLength=0.6), doc)
polar = math.radians(110)
points = [App.Vector(20 * math.sin(polar) * math.cos(a), 20 * math.sin(polar) * math.sin(a), 20 * math.cos(polar))
          for a in (2 * math.pi * (k + 0.5) / 16 for k in range(16))]
boundary = st.make_boundary(bone, points, inside=(0, 0, 20))
template = st.make_template(boundary, thickness=2.0, insertion=(0, 0, -1))
doc.recompute()
V, F = st_bridge.mesh_to_arrays(template.Mesh)
report = st_bridge.kernel().check_solid(V, F)
print("RESULT " + json.dumps({"valid": report["valid"], "skirt_area": template.SkirtArea.Value,
                              "removable": template.Removable, "lowest": float(V[:, 2].min()),
                              "status": template.Status, "state": list(template.State)}))

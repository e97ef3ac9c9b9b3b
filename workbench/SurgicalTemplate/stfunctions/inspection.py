"""The inspection of a guide or template on its bone (inspect), and the thickness map's colours."""
import FreeCAD as App

import st_bridge
from stobjects.base import kind_of


def thickness_colour(distance, thickness, clearance=0.0, tolerance=0.01):
    """The thickness map's colour (r, g, b in 0..1) of a distance from the bone (mm): red in the bone,
    green where the guide seats, through yellow to blue at the outer surface, grey beyond (sleeves)."""
    if distance < -tolerance:
        return (0.85, 0.15, 0.12)
    top = clearance + thickness
    if distance > top * 1.25:
        return (0.62, 0.64, 0.68)
    t = min(max((distance - clearance) / max(thickness, 1e-9), 0.0), 1.0)
    stops = ((0.0, (0.16, 0.70, 0.28)), (0.5, (0.95, 0.80, 0.15)), (1.0, (0.20, 0.45, 0.85)))
    for (t0, c0), (t1, c1) in zip(stops, stops[1:]):
        if t <= t1:
            u = (t - t0) / (t1 - t0)
            return tuple(a + (b - a) * u for a, b in zip(c0, c1))
    return stops[-1][1]


def inspect(obj, show=True, tolerance=0.01):
    """Inspects a guide or template on its bone with the kernel: {passed, summary, solid, vertices_in_bone,
    deepest_in_bone, seated_vertices, bores: [{name, margin, open}], face_distance (per facet, mm from
    the bone, negative inside it), thickness, clearance}. With `show` in the GUI, the facets are coloured
    by thickness_colour (the thickness map; recomputing the object removes it)."""
    kind = kind_of(obj)
    if kind not in ("Guide", "Template"):
        raise ValueError(f"{obj.Label}: only a guide or a template can be inspected")
    shell = obj.Shell if kind == "Guide" else obj
    if shell is None or shell.Boundary is None or shell.Boundary.Bone is None:
        raise ValueError(f"{obj.Label}: not on a bone")
    if obj.Mesh.CountFacets == 0:
        raise ValueError(f"{obj.Label}: the mesh is empty (recompute it first)")
    k = st_bridge.kernel()
    V, F = st_bridge.mesh_to_arrays(obj.Mesh)
    tubes = [t.Proxy.spec(t) for t in obj.Tubes] if kind == "Guide" else []
    clearance, thickness = float(shell.Clearance.Value), float(shell.Thickness.Value)
    r = st_bridge.call(k.inspect_guide, V, F, *st_bridge.bone_arrays(shell.Boundary.Bone), tubes, clearance,
                       tolerance)
    d = r.pop("vertex_distance")
    r["face_distance"] = [float(x) for x in d[F].mean(axis=1)]  # FreeCAD keeps the facet order
    r["thickness"], r["clearance"] = thickness, clearance
    if show and App.GuiUp:
        if "ThicknessMap" not in obj.PropertiesList:
            # An output that touches nothing: showing the map does not make the guide recompute.
            obj.addProperty("App::PropertyColorList", "ThicknessMap", "Validation",
                            "Facet colours of the last inspection (distance from the bone)", 8 | 16)
            obj.setEditorMode("ThicknessMap", 2)
        obj.ThicknessMap = [thickness_colour(x, thickness, clearance, tolerance) for x in r["face_distance"]]
        obj.ViewObject.Coloring = True
    return r

"""The inspection of a guide or template on its bone (inspect), and the thickness map's colours."""
import FreeCAD as App
import numpy as np

import st_bridge
from stobjects.base import kind_of


BLOCKED = (0.80, 0.20, 0.80)  # facets that meet the bone when the guide comes off


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


def stability(template, bone, direction, arrays=None):
    """Will the guide stay put: the kernel's analyse_stability of the template's inner surface (its
    first InnerFaces facets) on the bone arrays `bone`, pressed along `direction`; the press point among
    the template's other vertices. `arrays`: the template's mesh as (vertices, triangles) when the
    caller has read it already."""
    V, F = arrays if arrays is not None else st_bridge.mesh_to_arrays(template.Mesh)
    n = int(template.InnerFaces)
    if n <= 0 or n > len(F):
        return None
    inner = F[:n]
    outside = np.ones(len(V), dtype=bool)
    outside[inner.ravel()] = False
    outer = V[outside]
    resolution = float(template.Resolution.Value) or float(template.Thickness.Value) / 8.0
    reach = float(template.Clearance.Value) + 0.25 * resolution
    return st_bridge.call(st_bridge.kernel().analyse_stability, V, inner, *bone, st_bridge.vec(direction),
                          reach=reach, outer_points=outer if len(outer) else None,
                          toward_bone=True)  # the solid's facets face out of it: into the bone


def parts(guide, V, F):
    """The checks of a cutting guide's slots and labels on its finished mesh (V, F): each slot's blade path
    swept over the planned cut against the guide's triangles (exact tests, the kernel's check_blade_path),
    each label's depth, the wall left under it and its distance from sleeves and slots as the kernel laid
    it. [{name, check, passed, result}]; a guide recomputed before this version lacks its placements and
    says so."""
    k = st_bridge.kernel()
    out = []
    laid, labels = guide.Proxy.placed_of(guide)
    for slot in guide.Proxy.slots_of(guide):
        placed = laid.get(slot.get("name"))
        if placed is None:
            out.append({"name": slot.get("name", ""), "check": "blade path", "passed": False,
                        "result": "not checked: recompute the guide"})
            continue
        b = st_bridge.call(k.check_blade_path, V, F, slot, placed)
        at = b["blocked_at"]
        out.append({"name": slot["name"], "check": "blade path", "passed": bool(b["free"]),
                    "result": f"free over {slot['length']:.1f} mm, {placed['width']:.2f} mm wide" if b["free"] else
                    f"BLOCKED near ({at[0]:.2f}, {at[1]:.2f}, {at[2]:.2f})"})
    for label in labels:
        wall, clear = label.get("min_wall"), label.get("min_clearance")
        out.append({"name": label["name"], "check": f"{label['mode']} \"{label['text']}\"", "passed": True,
                    "result": f"{label['depth']:.2f} mm deep" + (f", wall under it {wall:.2f} mm" if wall else "") +
                    (f", {clear:.1f} mm from the nearest sleeve or slot" if clear is not None else "")})
    return out


def inspect(obj, show=True, tolerance=0.01):
    """Inspects a guide or template on its bone with the kernel: {passed, summary, solid, vertices_in_bone,
    deepest_in_bone, seated_vertices, bores: [{name, margin, open}], face_distance (per facet, mm from
    the bone, negative inside it), thickness, clearance, removal: None, or {removable, direction,
    blocking: [[x, y, z]], blocked_faces} along the template's InsertionUsed, stability: None, or the
    kernel's analyse_stability of the template's inner surface pressed along it (score, free_motions,
    worst_motion, press_point, contact_points, ...), parts: a cutting guide's slot and label checks
    (parts)}. With `show` in the GUI, the facets are coloured by thickness_colour (the thickness map;
    recomputing the object removes it)."""
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
    bone = st_bridge.bone_arrays(shell.Boundary.Bone)
    r = st_bridge.call(k.inspect_guide, V, F, *bone, tubes, clearance, tolerance)
    # The removal check along the template's insertion direction, when it has one.
    d = getattr(shell, "InsertionUsed", App.Vector(0, 0, 0))
    r["removal"] = None
    if d.Length > 0:
        removal = st_bridge.call(k.check_removal, V, F, *bone, st_bridge.vec(d))
        r["removal"] = {"removable": bool(removal["removable"]), "direction": st_bridge.vec(d),
                        "blocking": [[float(x) for x in p] for p in removal["blocking"]],
                        "blocked_faces": [int(x) for x in removal["blocked_faces"]]}
        # Shown beside the verdict (a printable guide that seats), not folded into it: bone far along
        # the way off (a neighbouring vertebra) may be out of the way in surgery.
        if not removal["removable"]:
            p = removal["blocking"][0]
            r["summary"] += f"; meets the bone coming off near ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f})"
        else:
            r["summary"] += "; comes off along its insertion direction"
    r["parts"] = parts(obj, V, F) if kind == "Guide" else []
    blocked = [p for p in r["parts"] if p["check"] == "blade path" and not p["passed"]]
    if blocked:
        r["passed"] = False
        r["summary"] += "; blade path blocked in " + ", ".join(f"slot '{p['name']}'" for p in blocked)
    r["stability"] = stability(shell, bone, d, (V, F) if shell is obj else None) if d.Length > 0 else None
    if r["stability"]:
        r["summary"] += f"; stability score {r['stability']['score']:.2f}"
    d = r.pop("vertex_distance")
    r["face_distance"] = [float(x) for x in d[F].mean(axis=1)]  # FreeCAD keeps the facet order
    r["thickness"], r["clearance"] = thickness, clearance
    if show and App.GuiUp:
        if "ThicknessMap" not in obj.PropertiesList:
            # An output that touches nothing: showing the map does not make the guide recompute.
            obj.addProperty("App::PropertyColorList", "ThicknessMap", "Validation",
                            "Facet colours of the last inspection (distance from the bone)", 8 | 16)
            obj.setEditorMode("ThicknessMap", 2)
        colours = [thickness_colour(x, thickness, clearance, tolerance) for x in r["face_distance"]]
        if r["removal"]:
            # Facets that meet the bone on the way off, in the map's warning colour.
            colours = [BLOCKED if b else c for c, b in zip(colours, r["removal"]["blocked_faces"])]
        obj.ThicknessMap = colours
        obj.ViewObject.Coloring = True
    return r

"""The drawing's saw-slot details: each slot's housing as the kernel placed it, an exact solid made with
OpenCASCADE from its placement (so that TechDraw's dimensions find its edges, as the sleeve details do
with the Tube solids), seen down the saw's travel, the slot's width dimensioned between its walls."""
import numpy as np

import FreeCAD as App
import Part


def slot_frame(row):
    """(origin, e, m, up) of a slot: e along the slot from its start to its end, m = -n across it, up
    against the saw's travel; (e, m, up) is right-handed."""
    n, d = row["normal"], row["travel"]
    e = np.cross(n, d)
    return row["origin"], e / np.linalg.norm(e), -n, -d


def slot_solid(row):
    """The housing of a slot with the slot cut through it, from the kernel's placement (row["placed"]:
    housing and slot extents along the slot, heights over the origin), in the scan's frame."""
    p = row["placed"]
    half, wall = row["width"] / 2.0, row["wall"]
    (h0, h1), (c0, c1) = p["housing"], p["cut"]
    (a0, a1), (s0, s1) = p["housing_extent"], p["extent"]
    housing = Part.makeBox(a1 - a0, 2 * (half + wall), h1 - h0, App.Vector(a0, -half - wall, h0))
    # The slot runs past the housing at an open end and through its top and foot.
    margin = 1.0
    slot = Part.makeBox(s1 - s0, 2 * half, (c1 - c0) + 2 * margin, App.Vector(s0, -half, min(c0, h0) - margin))
    solid = housing.cut(slot)
    o, e, m, up = slot_frame(row)
    solid.Placement = App.Placement(App.Matrix(e[0], m[0], up[0], o[0], e[1], m[1], up[1], o[1],
                                               e[2], m[2], up[2], o[2], 0, 0, 0, 1))
    return solid


def width_vertices(view, row):
    """Two vertices of a slot's detail across the slot at one place along it: ('VertexI', 'VertexJ') with
    the same x and y apart by the slot's width (the walls' top corners), from a recomputed view."""
    points = []
    i = 0
    while True:
        try:
            v = view.getVertexByIndex(i)
        except Exception:  # past the last vertex
            break
        if v is None:
            break
        points.append((i, v.Point))
        i += 1
    w = row["width"]
    for i, a in points:
        for j, b in points:
            if j > i and abs(a.x - b.x) < 1e-6 and abs(abs(a.y - b.y) - w) < 1e-6:
                return f"Vertex{i}", f"Vertex{j}"
    raise RuntimeError(f"slot '{row['name']}': no vertices across the slot in its detail view")


def slot_table(builder, rows, corner, size, text_width):
    """The slots' table (plane, travel, blade, width, closed ends), its upper right corner at `corner`,
    columns as wide as text_width(text, size) says; returns its lower left corner. Also a sheet in the
    drawing's data, like the other tables."""
    head = ["Slot", "Origin X", "Origin Y", "Origin Z", "Normal X", "Normal Y", "Normal Z", "Travel X", "Travel Y",
            "Travel Z", "Blade", "Width", "Closed"]
    table = [head] + [[r["name"], *(f"{c:.2f}" for c in r["origin"]), *(f"{c:.3f}" for c in r["normal"]),
                       *(f"{c:.3f}" for c in r["travel"]), f"{r['blade']:.2f}", f"{r['width']:.2f}",
                       "+".join(r["closed"]) or "open"] for r in rows]
    widths = [text_width(max((t[i] for t in table), key=len), size) + 1.6 * size for i in range(len(head))]
    row_h = 2.0 * size
    sheet = builder.add("Spreadsheet::Sheet", "DrawingSlotTable", f"{builder.guide.Label} slot table")
    builder.group.addObject(sheet)
    builder.sheet_table(sheet, 0, table, 1, widths, size, row_h)
    w, h = sum(widths), row_h * len(table)
    builder.drawn_table("SlotTable", table, widths, row_h, size, corner[0] - w, corner[1], 1)
    return corner[0] - w, corner[1] - h


def slot_details(builder, rows, cells, fit_scale, scale_text):
    """One detail per slot in the given cells ((cx, cy, cell width, cell height) each): its housing seen down
    the saw's travel, titled with its scale, the blade and clearance under it. Returns {slot name: view}."""
    views = {}
    t = builder.text
    for k, (r, (cx, cy, cw, ch)) in enumerate(zip(rows, cells)):
        p = r["placed"]
        along = p["housing_extent"][1] - p["housing_extent"][0]
        across = r["width"] + 2 * r["wall"]
        s = fit_scale(along, across, cw - 8.0 * t, ch - 6.5 * t)
        f = builder.feature(f"DrawingSlot{k}", f"{builder.guide.Label} slot {r['name']}", slot_solid(r))
        o, e, m, up = slot_frame(r)
        v = builder.part_view(f"Slot{k}", f"Slot {r['name']}", [f], up, e, s, cx, cy, "")
        v.HardHidden = True
        low = cy - across / 2.0 * s - 1.6 * t
        builder.annotation(f"Slot{k}Title", [f"SLOT {r['name']}  ({scale_text(s)})"], cx, low, t)
        builder.annotation(f"Slot{k}Blade", [f"blade {r['blade']:.2f} + 2 x {r['clearance']:.2f} clearance, "
                                             f"seen down the saw's travel"], cx, low - 1.4 * t, builder.small,
                           "Italic")
        views[r["name"]] = (v, r, s)
    return views


def dimension_slots(builder):
    """After a recompute: each slot detail's width between its walls."""
    out = {}
    for name, (v, r, s) in builder.slot_views.items():
        a, b = width_vertices(v, r)
        gap = 1.6 * builder.text
        along = (r["placed"]["housing_extent"][1] - r["placed"]["housing_extent"][0]) / 2.0
        out[name] = builder.dimension(v, [a, b], "DistanceY", "%.2f", along * s + gap, 0.0, f"{v.Label} width")
    return out

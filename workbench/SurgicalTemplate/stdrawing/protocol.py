"""The drill protocol of a guide: the numbers of its sleeves (sleeve_rows), saw slots (slot_rows),
labels (label_rows) and of its template, and the protocol as text tables (drill_protocol), which the
drawing's tables and its .txt file share.

    import SurgicalTemplate as st
    print(st.drill_protocol(guide))
"""
import datetime
import math

import numpy as np

from stobjects.guide import Guide


def vec(v):
    """A FreeCAD vector as a numpy array."""
    return np.array([float(v.x), float(v.y), float(v.z)])


def sleeve_rows(guide):
    """One dict per tube of the guide, in mm and degrees: name, entry, direction (unit, into the bone),
    azimuth (in the XY plane from +X toward +Y), elevation (from the XY plane, positive toward +Z),
    inner/outer diameter, length, offset, top (the sleeve's upper end on the axis), depth_to_entry
    (offset + length: from the sleeve top to the entry), depth (planned drilling depth into the bone,
    0 if not planned) and total_depth (depth_to_entry + depth, or None)."""
    rows = []
    for tube in guide.Tubes:
        d = vec(tube.Direction)
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            raise ValueError(f"{tube.Label}: the tube has no direction")
        d /= norm
        entry = vec(tube.Entry)
        offset, length = float(tube.Offset.Value), float(tube.Length.Value)
        depth = getattr(tube, "Depth", 0.0)   # a length property since 0.2; absent before
        depth = float(getattr(depth, "Value", depth) or 0.0)
        to_entry = offset + length
        rows.append({
            "name": tube.Label, "kind": getattr(tube, "Kind", "sleeve") or "sleeve", "entry": entry, "direction": d,
            "azimuth": math.degrees(math.atan2(d[1], d[0])),
            "elevation": math.degrees(math.asin(max(-1.0, min(1.0, d[2])))),
            "inner_diameter": float(tube.InnerDiameter.Value),
            "outer_diameter": float(tube.OuterDiameter.Value),
            "length": length, "offset": offset, "top": entry - d * to_entry,
            "depth_to_entry": to_entry, "depth": depth, "total_depth": to_entry + depth if depth > 0 else None,
        })
    return rows


def slot_rows(guide):
    """One dict per saw slot of the guide (mm): name, origin, normal (unit), travel (the saw's direction
    in the plane, unit: as planned, else as the kernel laid it), blade, clearance, width (blade + 2 x
    clearance), length, closed (its closed ends), placed (the kernel's placement, or None)."""
    rows = []
    laid = Guide.placed_of(guide)[0]
    for s in Guide.slots_of(guide):
        n = np.asarray(s["normal"], float)
        n /= np.linalg.norm(n)
        placed = laid.get(s["name"])
        travel = s.get("direction") if s.get("direction") is not None else (placed or {}).get("direction")
        if travel is None:
            raise ValueError(f"{guide.Label}: slot '{s['name']}' has no travel yet (recompute the guide)")
        d = np.asarray(travel, float)
        d = d - d.dot(n) * n
        d /= np.linalg.norm(d)
        clearance = float(s.get("clearance", 0.1))
        rows.append({"name": s["name"], "origin": np.asarray(s["origin"], float), "normal": n, "travel": d,
                     "blade": float(s["blade"]), "clearance": clearance, "width": float(s["blade"]) + 2 * clearance,
                     "length": float(s["length"]), "closed": list(s.get("closed", ["start", "end"])),
                     "wall": float(s.get("wall", 3.0)), "placed": placed})
    return rows


def label_rows(guide):
    """One dict per label of the guide: name, text, mode, at, height (cap height, mm), depth (mm)."""
    return [{"name": l.get("name") or f"label {i + 1}", "text": l["text"], "mode": l.get("mode", "engrave"),
             "at": np.asarray(l["at"], float), "height": float(l.get("height", 4.0)),
             "depth": float(l.get("depth", 0.6))} for i, l in enumerate(Guide.labels_of(guide))]


def template_info(guide, date):
    shell = guide.Shell
    box = guide.Mesh.BoundBox
    return {
        "case": guide.Label, "thickness": float(shell.Thickness.Value), "clearance": float(shell.Clearance.Value),
        "volume": float(guide.Mesh.Volume), "size": (box.XLength, box.YLength, box.ZLength),
        "sleeves": len(guide.Tubes), "date": date,
    }


def _num(x):
    """Three decimals, or six when three would round (so that sums can be checked to 1e-6)."""
    return f"{x:.3f}" if abs(x - round(x, 3)) < 1e-9 else f"{x:.6f}"


def drill_protocol(guide, date=None):
    """The drill protocol of a guide as text: one table row per sleeve or pin (mm, degrees), then the saw
    slots and the labels when it has them."""
    date = date or datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    info = template_info(guide, date)
    lines = [
        "Surgical Template drill protocol",
        f"Case: {info['case']}",
        f"Date: {date}",
        f"Template: thickness {info['thickness']:.2f} mm, clearance {info['clearance']:.2f} mm, "
        f"volume {info['volume']:.1f} mm^3, size {' x '.join(f'{s:.1f}' for s in info['size'])} mm",
        "",
        "Units: mm and degrees, in the coordinates of the bone scan.",
        "Direction: unit vector of drilling, into the bone. Azimuth: in the XY plane from +X toward +Y.",
        "Elevation: from the XY plane, positive toward +Z.",
        "Sleeve top: the upper end of the sleeve on its axis, where the drill enters the sleeve.",
        "Depth to entry = offset + length: drill travel from the sleeve top to the entry point on the bone.",
        "Total depth = depth to entry + planned depth into the bone (only when planned).",
        "Drill: the sleeve's inner diameter.",
        "",
    ]
    head = ["Sleeve", "Kind", "Entry X", "Entry Y", "Entry Z", "Dir X", "Dir Y", "Dir Z", "Azimuth", "Elevation",
            "Top X", "Top Y", "Top Z", "Depth to entry", "Planned depth", "Total depth", "Drill diameter"]
    table = [head]
    for r in sleeve_rows(guide):
        table.append([r["name"], r["kind"], *(f"{c:.3f}" for c in r["entry"]), *(f"{c:.5f}" for c in r["direction"]),
                      f"{r['azimuth']:.2f}", f"{r['elevation']:.2f}", *(f"{c:.3f}" for c in r["top"]),
                      _num(r["depth_to_entry"]), _num(r["depth"]) if r["depth"] > 0 else "-",
                      _num(r["total_depth"]) if r["total_depth"] is not None else "-", _num(r["inner_diameter"])])
    lines += _table(table)
    if len(table) == 1:
        lines.append("(no sleeves)")
    slots = slot_rows(guide)
    if slots:
        lines += ["", "Saw slots: the cut plane through the origin with its normal; the saw travels along the travel "
                  "direction; width = blade + 2 x clearance; closed: the ends the housing closes (start at -length/2 "
                  "across the travel, end at +length/2).", ""]
        table = [["Slot", "Origin X", "Origin Y", "Origin Z", "Normal X", "Normal Y", "Normal Z", "Travel X",
                  "Travel Y", "Travel Z", "Blade", "Width", "Length", "Closed"]]
        for r in slots:
            table.append([r["name"], *(f"{c:.3f}" for c in r["origin"]), *(f"{c:.5f}" for c in r["normal"]),
                          *(f"{c:.5f}" for c in r["travel"]), _num(r["blade"]), _num(r["width"]), _num(r["length"]),
                          "+".join(r["closed"]) or "open"])
        lines += _table(table)
    labels = label_rows(guide)
    if labels:
        lines += ["", "Labels: text engraved into (or embossed onto) the outer surface, centred near the point.", ""]
        table = [["Label", "Text", "Mode", "At X", "At Y", "At Z", "Cap height", "Depth"]]
        for r in labels:
            table.append([r["name"], r["text"], r["mode"], *(f"{c:.3f}" for c in r["at"]), _num(r["height"]),
                          _num(r["depth"])])
        lines += _table(table)
    return "\n".join(lines) + "\n"


def _table(table):
    """Markdown-like lines of a table (first row the head; first column left-aligned)."""
    widths = [max(len(row[i]) for row in table) for i in range(len(table[0]))]
    lines = []
    for k, row in enumerate(table):
        cells = [c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths))]
        lines.append("| " + " | ".join(cells) + " |")
        if k == 0:
            lines.append("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    return lines

"""The documentation drawing of a surgical guide: a TechDraw page with front, top and side views of
the guide, one dimensioned detail per sleeve, a table of the sleeves and the template, exported to
PDF and SVG, and a drill protocol as text.

    import SurgicalTemplate as st
    guide = st.load_case("examples/cases/maxilla-implants.json")
    st.make_drawing(guide, "out/maxilla.pdf")   # out/maxilla.pdf, .svg, .txt; returns the page and protocol

The guide is a mesh, and TechDraw projects a mesh turned into a Part shape as every triangle edge (a
black smear). So the views draw line drawings computed here from the mesh: its outlines (the contour
where the smoothed surface turns away from the viewer, interpolated inside the triangles so that the
lines are smooth), its sharp edges (creases of more than CREASE_ANGLE), and the sleeves from their exact
definition (cylinder outlines as lines, the top rims as circles and arcs); hidden parts removed by casting
rays through the mesh. These 3D edges are the Shape of one Part::Feature per view. The sleeve details
project the Tube objects themselves, exact solids, so TechDraw's dimensions find their edges.

Whole-page PDF/SVG export needs FreeCAD's GUI. Without it (freecadcmd, or Python with FreeCAD), the
document is saved to a temporary file and opened by FreeCAD's GUI in a subprocess under Xvfb, which
exports the page. Outputs are written whole or not at all.
"""
import datetime
import json
import math
import os
import shutil
import signal
import subprocess
import tempfile
import traceback

import numpy as np

import FreeCAD as App
import Part

import st_bridge

__all__ = ["make_drawing", "drill_protocol", "sleeve_rows", "guide_lines"]

_HERE = os.path.dirname(os.path.abspath(__file__))

CREASE_ANGLE = 40.0   # degrees between face normals above which an edge of the mesh is drawn
SCALES = (20.0, 10.0, 5.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.0, 0.5, 0.4, 0.25, 0.2, 0.1)
TEXT = 3.5            # mm, text on the page
SMALL = 2.5           # mm, small text (table, notes)
EXPORT_TIMEOUT = 180  # s, the GUI subprocess

# Templates that come with FreeCAD's TechDraw; page coordinates in mm, origin at the lower left.
_PAPERS = {
    "A3": {"template": "A3_LandscapeTD.svg", "size": (420.0, 297.0), "work": (10.0, 10.0, 410.0, 287.0),
           "title": (220.0, 10.0, 410.0, 70.0)},
    "A4": {"template": "A4_LandscapeTD.svg", "size": (297.0, 210.0), "work": (10.0, 10.0, 287.0, 200.0),
           "title": (147.0, 10.0, 287.0, 57.0)},
}

# Main views: name, caption, TechDraw Direction (from the object to the viewer), XDirection.
# First-angle arrangement (ISO, TechDraw's default): top view below the front view, the view from
# the left to the right of it.
_VIEWS = (
    ("Front", "FRONT  (view along +Y)", (0.0, -1.0, 0.0), (1.0, 0.0, 0.0)),
    ("Top", "TOP  (view along -Z)", (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),
    ("Left", "LEFT  (view along +X)", (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
)


# ---------------------------------------------------------------------------------------------
# The numbers: sleeves and template


def _vec(v):
    return np.array([float(v.x), float(v.y), float(v.z)])


def sleeve_rows(guide):
    """One dict per tube of the guide, in mm and degrees: name, entry, direction (unit, into the bone),
    azimuth (in the XY plane from +X toward +Y), elevation (from the XY plane, positive toward +Z),
    inner/outer diameter, length, offset, top (the sleeve's upper end on the axis), depth_to_entry
    (offset + length: from the sleeve top to the entry), depth (planned drilling depth into the bone,
    0 if not planned) and total_depth (depth_to_entry + depth, or None)."""
    rows = []
    for tube in guide.Tubes:
        d = _vec(tube.Direction)
        norm = float(np.linalg.norm(d))
        if norm < 1e-12:
            raise ValueError(f"{tube.Label}: the tube has no direction")
        d /= norm
        entry = _vec(tube.Entry)
        offset, length = float(tube.Offset.Value), float(tube.Length.Value)
        depth = getattr(tube, "Depth", 0.0)   # a length property since 0.2; absent before
        depth = float(getattr(depth, "Value", depth) or 0.0)
        to_entry = offset + length
        rows.append({
            "name": tube.Label, "entry": entry, "direction": d,
            "azimuth": math.degrees(math.atan2(d[1], d[0])),
            "elevation": math.degrees(math.asin(max(-1.0, min(1.0, d[2])))),
            "inner_diameter": 2.0 * float(tube.InnerRadius.Value),
            "outer_diameter": 2.0 * float(tube.OuterRadius.Value),
            "length": length, "offset": offset, "top": entry - d * to_entry,
            "depth_to_entry": to_entry, "depth": depth, "total_depth": to_entry + depth if depth > 0 else None,
        })
    return rows


def _template_info(guide, date):
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
    """The drill protocol of a guide as text: one table row per sleeve (mm, degrees)."""
    date = date or datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    info = _template_info(guide, date)
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
    head = ["Sleeve", "Entry X", "Entry Y", "Entry Z", "Dir X", "Dir Y", "Dir Z", "Azimuth", "Elevation",
            "Top X", "Top Y", "Top Z", "Depth to entry", "Planned depth", "Total depth", "Drill diameter"]
    table = [head]
    for r in sleeve_rows(guide):
        table.append([r["name"], *(f"{c:.3f}" for c in r["entry"]), *(f"{c:.5f}" for c in r["direction"]),
                      f"{r['azimuth']:.2f}", f"{r['elevation']:.2f}", *(f"{c:.3f}" for c in r["top"]),
                      _num(r["depth_to_entry"]), _num(r["depth"]) if r["depth"] > 0 else "-",
                      _num(r["total_depth"]) if r["total_depth"] is not None else "-", _num(r["inner_diameter"])])
    widths = [max(len(row[i]) for row in table) for i in range(len(head))]
    for k, row in enumerate(table):
        cells = [c.ljust(w) if i == 0 else c.rjust(w) for i, (c, w) in enumerate(zip(row, widths))]
        lines.append("| " + " | ".join(cells) + " |")
        if k == 0:
            lines.append("|" + "|".join("-" * (w + 2) for w in widths) + "|")
    if len(table) == 1:
        lines.append("(no sleeves)")
    return "\n".join(lines) + "\n"


# ---------------------------------------------------------------------------------------------
# Line drawings of the guide mesh


class _LineModel:
    """The guide mesh prepared once for the line drawings of all views: face normals, the edges with
    their faces, and normals per face corner that are smooth within a surface and split at creases
    (so that outlines do not bend towards sharp edges)."""

    def __init__(self, V, F, crease_angle=CREASE_ANGLE):
        V = np.asarray(V, dtype=np.float64)
        F = np.asarray(F, dtype=np.int64)
        n, m = len(V), len(F)
        self.V, self.F = V, F
        a, b, c = V[F[:, 0]], V[F[:, 1]], V[F[:, 2]]
        cross = np.cross(b - a, c - a)
        area2 = np.linalg.norm(cross, axis=1)
        self.normals = cross / np.maximum(area2, 1e-300)[:, None]
        self.cos_crease = math.cos(math.radians(crease_angle))
        # Edges; the half-edge of corner k of face f runs from F[f, k] to F[f, k + 1].
        start, end = F.ravel(), np.roll(F, -1, axis=1).ravel()
        key = np.minimum(start, end) * n + np.maximum(start, end)
        order = np.argsort(key, kind="stable")
        uniq, first, count = np.unique(key[order], return_index=True, return_counts=True)
        self.edge_of_half = np.empty(3 * m, dtype=np.int64)
        self.edge_of_half[order] = np.repeat(np.arange(len(uniq)), count)
        self.edge_vertices = np.stack([uniq // n, uniq % n], axis=1)
        second = order[np.minimum(first + 1, len(order) - 1)] // 3
        self.edge_faces = np.stack([order[first] // 3, np.where(count == 2, second, order[first] // 3)], axis=1)
        self.edge_manifold = count == 2
        lengths = np.linalg.norm(V[self.edge_vertices[:, 0]] - V[self.edge_vertices[:, 1]], axis=1)
        self.edge_scale = float(np.median(lengths))
        # Corner normals: area-weighted normals of the faces around the corner's vertex that lie within
        # the crease angle of the corner's own face.
        corner_vertex, corner_face = F.ravel(), np.repeat(np.arange(m), 3)
        by_vertex = np.argsort(corner_vertex, kind="stable")
        valence = np.bincount(corner_vertex, minlength=n)
        first_corner = np.concatenate([[0], np.cumsum(valence)[:-1]])
        k = valence[corner_vertex[by_vertex]]
        me = np.repeat(by_vertex, k)
        within = np.arange(k.sum()) - np.repeat(np.cumsum(k) - k, k)
        other = by_vertex[np.repeat(first_corner[corner_vertex[by_vertex]], k) + within]
        fm, fo = corner_face[me], corner_face[other]
        w = area2[fo] * (np.einsum("ij,ij->i", self.normals[fm], self.normals[fo]) > self.cos_crease)
        cn = np.stack([np.bincount(me, weights=w * self.normals[fo, i], minlength=3 * m) for i in range(3)], axis=1)
        self.corner_normals = cn / np.maximum(np.linalg.norm(cn, axis=1), 1e-300)[:, None]

    def outlines(self, d, skip):
        """Contour segments where the corner-normal field turns from the viewer (direction d points to
        the viewer): points (k,2,3) and chaining keys (k,2) (edge ids)."""
        F, V = self.F, self.V
        g = (self.corner_normals @ d).reshape(-1, 3)
        s = g > 0
        faces = np.nonzero(s.any(axis=1) & ~s.all(axis=1) & ~skip)[0]
        gs, ss = g[faces], s[faces]
        pts, keys = [], []
        for k in range(3):
            k1 = (k + 1) % 3
            crosses = ss[:, k] != ss[:, k1]
            t = gs[:, k] / np.where(crosses, gs[:, k] - gs[:, k1], 1.0)
            pts.append(V[F[faces, k]] * (1.0 - t)[:, None] + V[F[faces, k1]] * t[:, None])
            keys.append(np.where(crosses, self.edge_of_half[3 * faces + k], -1))
        pts, keys = np.stack(pts, axis=1), np.stack(keys, axis=1)
        pick = np.argsort(keys < 0, axis=1, kind="stable")[:, :2]   # the two edges the contour crosses
        rows = np.arange(len(faces))[:, None]
        return pts[rows, pick], keys[rows, pick]

    def creases(self, d, skip):
        """Sharp edges (dihedral angle above the crease angle, or not shared by two faces) that are not
        between two faces turned away from the viewer, nor between two faces in `skip`: points (k,2,3),
        chaining keys (k,2) (vertex ids)."""
        fa, fb = self.edge_faces[:, 0], self.edge_faces[:, 1]
        na, nb = self.normals[fa], self.normals[fb]
        sharp = ~self.edge_manifold | (np.einsum("ij,ij->i", na, nb) < self.cos_crease)
        facing = (na @ d > 0) | (nb @ d > 0) | ~self.edge_manifold
        e = np.nonzero(sharp & facing & ~(skip[fa] & skip[fb]))[0]
        ev = self.edge_vertices[e]
        return self.V[ev], ev


def _chains(keys):
    """Segments (k,2 endpoint keys) ordered into chains: lists of (segment, reversed)."""
    ends = {}
    for i, (a, b) in enumerate(keys.tolist()):
        ends.setdefault(a, []).append((i, 0))
        ends.setdefault(b, []).append((i, 1))
    used = np.zeros(len(keys), dtype=bool)

    def walk(i, rev):
        chain = [(i, rev)]
        used[i] = True
        while True:
            s, r = chain[-1]
            at = ends[keys[s][0 if r else 1]]
            nxt = [(j, e) for j, e in at if not used[j]]
            if len(at) != 2 or not nxt:
                return chain
            j, e = nxt[0]
            used[j] = True
            chain.append((j, e == 1))

    out = []
    for at in ends.values():        # open chains start where not exactly two segments meet
        if len(at) != 2:
            out += [walk(i, e == 1) for i, e in at if not used[i]]
    out += [walk(i, False) for i in range(len(keys)) if not used[i]]   # closed loops
    return out


def _simplify(points, tol):
    """Douglas-Peucker on a polyline (k,3)."""
    keep = np.zeros(len(points), dtype=bool)
    keep[[0, -1]] = True
    stack = [(0, len(points) - 1)]
    while stack:
        i, j = stack.pop()
        if j <= i + 1:
            continue
        ab = points[j] - points[i]
        p = points[i + 1:j] - points[i]
        ll = float(ab @ ab)
        dist = np.linalg.norm(p - np.outer(p @ ab / ll, ab) if ll > 1e-24 else p, axis=1)
        k = int(np.argmax(dist))
        if dist[k] > tol:
            keep[i + 1 + k] = True
            stack += [(i, i + 1 + k), (i + 1 + k, j)]
    return points[keep]


def _visible_polylines(pts, keys, hidden):
    """The visible runs of the chained segments, as point arrays."""
    out = []
    for chain in _chains(keys):
        run = []
        for s, rev in chain:
            if hidden[s]:
                if len(run) > 1:
                    out.append(np.array(run))
                run = []
                continue
            a, b = (pts[s][1], pts[s][0]) if rev else (pts[s][0], pts[s][1])
            run = run or [a]
            run.append(b)
        if len(run) > 1:
            out.append(np.array(run))
    return out


class _Sleeve:
    """A tube's sleeve as the guide mesh holds it: the exact cylinders reach down into the shell (the
    bore to the bone), found from the mesh vertices on them."""

    def __init__(self, tube, V, tol):
        self.name = tube.Label
        self.axis = _vec(tube.Direction) / np.linalg.norm(_vec(tube.Direction))   # into the bone
        self.entry = _vec(tube.Entry)
        self.R, self.r = float(tube.OuterRadius.Value), float(tube.InnerRadius.Value)
        self.top = float(tube.Offset.Value) + float(tube.Length.Value)
        self.tol = tol
        s, rad = self.coordinates(V)
        below = -(2.0 * self.R + 1.0)
        outer = (np.abs(rad - self.R) < tol) & (s > below) & (s < self.top + tol)
        inner = (np.abs(rad - self.r) < tol) & (s > below) & (s < self.top + tol)
        self.outer_from = float(s[outer].min()) if outer.any() else float(tube.Offset.Value)
        self.inner_from = float(s[inner].min()) if inner.any() else float(tube.Offset.Value)

    def coordinates(self, P):
        """(s, radius): distance outward from the entry along the axis, distance from the axis."""
        w = P - self.entry
        s = -(w @ self.axis)
        return s, np.linalg.norm(w + np.outer(s, self.axis), axis=1)

    def faces(self, centroids, normals):
        """Facets of the mesh on this sleeve's cylinders and top ring (drawn exactly instead)."""
        s, rad = self.coordinates(centroids)
        t = self.tol
        along = np.abs(normals @ self.axis)
        wall = along < 0.3
        outer = wall & (np.abs(rad - self.R) < t) & (s > self.outer_from - t) & (s < self.top + t)
        inner = wall & (np.abs(rad - self.r) < t) & (s > self.inner_from - t) & (s < self.top + t)
        ring = (along > 0.95) & (np.abs(s - self.top) < t) & (rad > self.r - t) & (rad < self.R + t)
        return outer | inner | ring

    def point(self, s):
        """The point(s) on the axis at distance(s) s outward from the entry."""
        return self.entry - np.multiply.outer(s, self.axis)

    def edges(self, d, hidden):
        """The sleeve's visible exact edges in a view: cylinder outlines (lines) and top rims (circles).
        hidden(points): which points the guide hides in this view."""
        out = []
        side = np.cross(self.axis, d)
        if np.linalg.norm(side) > 1e-6:
            side /= np.linalg.norm(side)
            for radius, s0 in ((self.R, self.outer_from), (self.r, self.inner_from)):
                s = np.linspace(s0, self.top, max(8, int((self.top - s0) / 0.05)))
                for sign in (1.0, -1.0):
                    p = self.point(s) + side * (sign * radius)
                    for run in _runs(~hidden(p)):
                        a, b = p[run[0]], p[run[-1]]
                        if np.linalg.norm(b - a) > 1e-6:
                            out.append(Part.LineSegment(App.Vector(*a), App.Vector(*b)).toShape())
        u = np.cross(self.axis, [1.0, 0.0, 0.0] if abs(self.axis[0]) < 0.9 else [0.0, 1.0, 0.0])
        u /= np.linalg.norm(u)
        v = np.cross(self.axis, u)
        c = self.point(self.top)
        phi = np.linspace(0.0, 2.0 * math.pi, 181)[:-1]
        for radius in (self.R, self.r):
            p = c + radius * (np.outer(np.cos(phi), u) + np.outer(np.sin(phi), v))
            seen = ~hidden(p)
            if seen.all():
                out.append(Part.makeCircle(radius, App.Vector(*c), App.Vector(*(-self.axis))))
                continue
            for run in _runs(seen, cyclic=True):
                if len(run) >= 3:
                    a, m, b = p[run[0]], p[run[len(run) // 2]], p[run[-1]]
                    out.append(Part.Arc(App.Vector(*a), App.Vector(*m), App.Vector(*b)).toShape())
        return out


def _runs(flags, cyclic=False):
    """Index lists of the runs of True in a boolean array (joined across the end when cyclic)."""
    idx = np.nonzero(flags)[0]
    if len(idx) == 0:
        return []
    runs = np.split(idx, np.nonzero(np.diff(idx) > 1)[0] + 1)
    if cyclic and len(runs) > 1 and runs[0][0] == 0 and runs[-1][-1] == len(flags) - 1:
        runs = [np.concatenate([runs[-1], runs[0]])] + runs[1:-1]
    return [list(r) for r in runs]


def guide_lines(guide, views, arrays=None):
    """The visible lines of a guide seen along each (direction, x_direction) of `views`, as Part
    compounds of 3D edges (TechDraw projects them as they are). `arrays`: the guide mesh as
    (vertices, triangles), when already at hand."""
    V, F = arrays if arrays is not None else st_bridge.mesh_to_arrays(guide.Mesh)
    model = _LineModel(V, F)
    centroids = model.V[model.F].mean(axis=1)
    tol = max(0.03, 3.0 * float(guide.Tolerance.Value)) if hasattr(guide, "Tolerance") else 0.03
    sleeves = [_Sleeve(t, model.V, tol) for t in guide.Tubes]
    skip = np.zeros(len(model.F), dtype=bool)
    for s in sleeves:
        skip |= s.faces(centroids, model.normals)
    # Outlines lie within a triangle of the true contour: the tolerance of the hidden-line test.
    mesh_tol = 0.02 + 0.5 * model.edge_scale
    caster = st_bridge.kernel().RayCaster(model.V, model.F)  # hidden = a facet in front, towards the viewer
    out = []
    for direction, xdir in views:
        d = np.asarray(direction, dtype=np.float64)
        x = np.asarray(xdir, dtype=np.float64)
        d, x = d / np.linalg.norm(d), x / np.linalg.norm(x)
        polylines = []
        for pts, keys in (model.outlines(d, skip), model.creases(d, skip)):
            if len(pts):
                polylines += _visible_polylines(pts, keys, caster.occluded(pts.mean(axis=1), d, mesh_tol))
        edges = []
        for p in polylines:
            p = _simplify(p, 0.01)
            if len(p) == 2:
                edges.append(Part.LineSegment(App.Vector(*p[0]), App.Vector(*p[1])).toShape())
            else:
                edges.append(Part.makePolygon([App.Vector(*q) for q in p]))
        for s in sleeves:
            edges += s.edges(d, lambda p: caster.occluded(p, d, 0.05 + tol))
        out.append(Part.makeCompound(edges))
    return out


# ---------------------------------------------------------------------------------------------
# The page


_PX = 25.4 / 96.0   # mm per unit of a spreadsheet view (TechDraw draws its cells in 96 dpi pixels)


def _paper(paper):
    key = str(paper).upper()
    if key not in _PAPERS:
        raise ValueError(f"paper {paper!r}: use one of {', '.join(_PAPERS)}")
    spec = dict(_PAPERS[key], name=key)
    spec["path"] = os.path.join(App.getResourceDir(), "Mod", "TechDraw", "Templates", spec["template"])
    if not os.path.exists(spec["path"]):
        raise RuntimeError(f"TechDraw template {spec['path']} not found (is FreeCAD's TechDraw installed?)")
    return spec


def _scale_text(s):
    return f"{s:g}:1" if s >= 1 else f"1:{1.0 / s:g}"


def _fit_scale(width, height, room_w, room_h):
    for s in SCALES:
        if width * s <= room_w and height * s <= room_h:
            return s
    return SCALES[-1]


class _Builder:
    """Adds the drawing's objects to the document and remembers them (to undo by hand when the
    document keeps no undo history)."""

    def __init__(self, doc, guide, paper, date):
        self.doc, self.guide, self.paper, self.date = doc, guide, paper, date
        self.created = []
        self.dimensions = {}

    def add(self, kind, name, label=None):
        obj = self.doc.addObject(kind, name)
        self.created.append(obj.Name)
        if label:
            obj.Label = label
        return obj

    def remove_created(self):
        for name in reversed(self.created):
            if self.doc.getObject(name) is not None:
                self.doc.removeObject(name)

    # The page: regions (x0, y0, x1, y1) in page mm: views at the top left, template data at the top
    # right, a band of sleeve details, the sleeve table beside the title block.
    def build(self):
        g, p = self.guide, self.paper
        (wx0, wy0, wx1, wy1), (tx0, _, _, ty1) = p["work"], p["title"]
        a3 = p["name"] == "A3"
        self.text = TEXT if a3 else 3.0
        self.small = SMALL if a3 else 2.0
        m = 5.0
        plan = self.detail_plan(wx1 - wx0 - 2 * m, 60.0 if a3 else 45.0)
        band = plan[1] * plan[4] if plan else 0.0
        self.page = self.add("TechDraw::DrawPage", "Drawing", f"{g.Label} drawing")
        template = self.add("TechDraw::DrawSVGTemplate", "DrawingTemplate", f"{g.Label} template")
        template.Template = p["path"]
        self.page.Template = template
        self.page.addProperty("App::PropertyString", "SurgicalGuide", "Surgical Template", "The guide drawn here")
        self.page.SurgicalGuide = g.Name
        self.group = self.add("App::DocumentObjectGroup", "DrawingData", f"{g.Label} drawing data")
        self.page.addProperty("App::PropertyString", "DrawingData", "Surgical Template", "Its lines and tables")
        self.page.DrawingData = self.group.Name
        info = self.info_table((wx1 - m, wy1 - m))
        top = (wx0 + m, ty1 + band + 2 * m, info[0] - 2 * m, wy1 - m)
        self.main_views(top)
        self.details(plan, wx0 + m, ty1 + m + band)
        self.sleeve_table((wx0 + m, wy0 + m, tx0 - m, ty1))
        scale = _scale_text(self.scale)
        # The fields of the A3 and the A4 template.
        texts = {"FC-Title": g.Label, "Subtitle": "Surgical guide: sleeves and drilling plan",
                 "AuthorName": "Surgical Template", "Designed_by_Name": "Surgical Template",
                 "CreationDate": self.date[:10], "FC-Date": self.date[:10], "FC-Scale": scale, "FC-SC": scale,
                 "DrawingNumber": g.Label, "Drawing_number": g.Label, "SheetNumber": "1 / 1", "FC-SH": "1 / 1",
                 "Weight": "", "SupervisorName": "", "CheckDate": ""}
        template.EditableTexts = {k: texts.get(k, v) for k, v in template.EditableTexts.items()}
        return self.page

    def feature(self, name, label, shape):
        f = self.add("Part::Feature", name, label)
        f.Shape = shape
        self.group.addObject(f)
        if App.GuiUp:
            f.ViewObject.Visibility = False
        return f

    def part_view(self, name, label, sources, direction, xdir, scale, x, y, caption):
        v = self.add("TechDraw::DrawViewPart", name, label)
        self.page.addView(v)
        v.Source = sources
        v.Direction, v.XDirection = App.Vector(*direction), App.Vector(*xdir)
        v.ScaleType = "Custom"
        v.Scale = scale
        v.X, v.Y = x, y
        v.Caption = caption
        return v

    def annotation(self, name, lines, x, y, size, style="Normal"):
        a = self.add("TechDraw::DrawViewAnnotation", name)
        self.page.addView(a)
        a.Text = lines
        a.TextSize = size
        a.TextStyle = style
        a.X, a.Y = x, y
        return a

    def main_views(self, region):
        x0, y0, x1, y1 = region
        box = self.guide.Mesh.BoundBox
        X, Y, Z = box.XLength, box.YLength, box.ZLength
        gap = 4.0 * self.text   # room for the sleeve names and the view titles
        self.scale = s = _fit_scale(X + Y, Z + Y, x1 - x0 - gap - 4.0 * self.text, y1 - y0 - 2.0 * gap)
        places = {"Front": (X * s / 2.0, -Z * s / 2.0), "Top": (X * s / 2.0, -Z * s - gap - Y * s / 2.0),
                  "Left": (X * s + gap + Y * s / 2.0, -Z * s / 2.0)}
        shapes = guide_lines(self.guide, [(d, x) for _, _, d, x in _VIEWS], self.arrays)
        self.views = {}
        placed = []   # (object, its box on the page)
        for (name, title, d, x), shape in zip(_VIEWS, shapes):
            f = self.feature(f"DrawingLines{name}", f"{self.guide.Label} lines {name}", shape)
            cx, cy = places[name]
            v = self.part_view(f"View{name}", name, [f], d, x, s, cx, cy, "")
            self.views[name] = v
            half = _projected_half_size(shape, d, x) * s
            mine = [(v, (cx - half[0], cy - half[1], cx + half[0], cy + half[1]))]
            mine += self.sleeve_labels(v, shape, d, x, s, cx, cy)
            low = min(box[1] for _, box in mine) - 1.2 * self.text
            t = self.annotation(f"View{name}Title", [title], cx, low, self.text)
            placed += mine + [(t, _text_box(title, self.text, cx, low))]
        # Centre the arrangement with its names and titles in the region.
        bx0, by0 = min(b[0] for _, b in placed), min(b[1] for _, b in placed)
        bx1, by1 = max(b[2] for _, b in placed), max(b[3] for _, b in placed)
        dx, dy = (x0 + x1 - bx0 - bx1) / 2.0, (y0 + y1 - by0 - by1) / 2.0
        for obj, _ in placed:
            obj.X, obj.Y = _length(obj.X) + dx, _length(obj.Y) + dy

    def sleeve_labels(self, view, shape, d, x, s, cx, cy):
        """Sleeve names beside their tops, outward along the projected axis: [(annotation, box)]."""
        d, x = np.array(d), np.array(x)
        frame = np.stack([x, np.cross(d, x)])
        box = shape.BoundBox
        corners = np.array([[px, py, pz] for px in (box.XMin, box.XMax) for py in (box.YMin, box.YMax)
                            for pz in (box.ZMin, box.ZMax)]) @ frame.T
        c = (corners.min(axis=0) + corners.max(axis=0)) / 2.0     # TechDraw centres a view on its box
        out = []
        for r in sleeve_rows(self.guide):
            q = -frame @ r["direction"]
            top = (frame @ r["top"] - c) * s
            R = r["outer_diameter"] / 2.0 * s
            if np.linalg.norm(q) > 0.35:
                at = top + q / np.linalg.norm(q) * (R + 0.9 * self.text)
            else:
                at = top + np.array([1.0, 1.0]) * (R + 0.5 * self.text)
            if any(np.linalg.norm(at - np.array([_length(o.X) - cx, _length(o.Y) - cy])) < 1.5 * self.text
                   for o, _ in out):
                continue
            a = self.annotation(f"{view.Name}Label", [r["name"]], cx + at[0], cy + at[1], self.text, "Bold")
            out.append((a, _text_box(r["name"], self.text, cx + at[0], cy + at[1])))
        return out

    def detail_plan(self, width, height):
        """(scale, lines, columns, cell width, cell height) of the sleeve details in a band, or None."""
        rows = sleeve_rows(self.guide)
        self.detail_scale = SCALES[0]
        if not rows:
            return None
        L = max(r["length"] for r in rows)
        D = max(r["outer_diameter"] for r in rows)
        best = None
        for lines in (1, 2, 3):
            cols = -(-len(rows) // lines)
            cw, ch = width / cols, height / lines
            s = _fit_scale(L, D, cw - 8.0 * self.text, ch - 6.5 * self.text)
            if best is None or s > best[0]:
                best = (s, lines, cols, cw, min(ch, D * s + 6.5 * self.text))
        self.detail_scale = best[0]
        return best

    def details(self, plan, x0, y1):
        """One view per sleeve, across the sleeve's seam, in cells below y1."""
        self.details_of = {}
        if plan is None:
            return
        s, lines, cols, cw, ch = plan
        rows = sleeve_rows(self.guide)
        for i, (r, tube) in enumerate(zip(rows, self.guide.Tubes)):
            row, col = divmod(i, cols)
            cx, cy = x0 + (col + 0.5) * cw, y1 - (row + 0.5) * ch + 0.8 * self.text
            a = r["direction"]
            d = np.cross(a, _seam_side(tube, a))
            d /= np.linalg.norm(d)
            v = self.part_view(f"Sleeve{i}", f"Sleeve {r['name']}", [tube], d, a, s, cx, cy, "")
            v.HardHidden = True
            R, rr = r["outer_diameter"] / 2.0 * s, r["inner_diameter"] / 2.0 * s
            low = cy - max(R, rr + 1.2 * self.text) - 1.4 * self.text
            self.annotation(f"Sleeve{i}Title", [f"SLEEVE {r['name']}  ({_scale_text(s)})"], cx, low, self.text)
            # Which end is which, outside the diameters: the drill enters at the top (left).
            ends = r["length"] / 2.0 * s + 1.6 * self.text + 2.2 * self.small
            self.annotation(f"Sleeve{i}Top", ["top"], cx - ends, cy, self.small, "Italic")
            self.annotation(f"Sleeve{i}Bone", ["bone"], cx + ends, cy, self.small, "Italic")
            self.details_of[tube.Name] = v

    def dimension(self, view, ref, kind, fmt, x, y, label):
        dim = self.add("TechDraw::DrawViewDimension", "Dimension", label)
        dim.Type = kind
        dim.References2D = [(view, ref)]
        dim.FormatSpec = fmt
        dim.MeasureType = "Projected"
        self.page.addView(dim)
        dim.X, dim.Y = x, y
        return dim

    def dimension_details(self):
        """After a recompute: diameters and length of each sleeve, on its edges found by geometry."""
        for r, tube in zip(sleeve_rows(self.guide), self.guide.Tubes):
            v = self.details_of[tube.Name]
            s = v.Scale
            edges = _view_edges(v)
            n_visible = len(v.getVisibleEdges())

            def pick(want, visible, score):
                found = [(score(e), i) for i, e in edges if (i < n_visible) == visible and want(e)]
                if not found:
                    raise RuntimeError(f"{tube.Label}: no edge for a dimension in its detail view")
                return f"Edge{max(found)[1]}"

            def straight(e, axis, length):
                a, b = e.Vertexes[0].Point, e.Vertexes[-1].Point
                dx, dy = abs(a.x - b.x), abs(a.y - b.y)
                along, across = (dx, dy) if axis == "x" else (dy, dx)
                return across < 1e-6 and abs(along - length) < 1e-3

            def mid(e):
                a, b = e.Vertexes[0].Point, e.Vertexes[-1].Point
                return (a + b) * 0.5

            L, R, rr = r["length"], r["outer_diameter"] / 2.0, r["inner_diameter"] / 2.0
            length = pick(lambda e: straight(e, "x", L), True, lambda e: mid(e).y)
            outer = pick(lambda e: straight(e, "y", 2 * R), True, lambda e: mid(e).x)
            inner = pick(lambda e: straight(e, "y", 2 * rr), False, lambda e: -mid(e).x)
            gap = 1.6 * self.text
            # The axis, beyond both ends (a cosmetic line needs the computed view); the drill enters at
            # the left, the sleeve top.
            half = L / 2.0 + 0.6 * self.text / s
            v.makeCosmeticLine(App.Vector(-half, 0, 0), App.Vector(half, 0, 0), 4, 0.18, (0.0, 0.0, 0.0))
            self.dimensions[tube.Name] = [
                self.dimension(v, length, "DistanceX", "%.2f", 0.0, R * s + gap, f"{v.Label} length"),
                self.dimension(v, outer, "DistanceY", "⌀%.2f", L / 2.0 * s + gap, 0.0, f"{v.Label} outer diameter"),
                self.dimension(v, inner, "DistanceY", "⌀%.2f", -L / 2.0 * s - gap, 0.0,
                               f"{v.Label} inner diameter"),
            ]

    def sheet_table(self, sheet, first_col, rows, head_rows, widths, size, row_h):
        """Fills a block of `sheet` (the table's data, for the user) and returns its cell range."""
        cols = [_column(first_col + i) for i in range(len(widths))]
        for j, row in enumerate(rows):
            for i, text in enumerate(row):
                sheet.set(f"{cols[i]}{j + 1}", "'" + text if text else "")
        for i, w in enumerate(widths):
            sheet.setColumnWidth(cols[i], int(round(w / _PX)))
        for j in range(len(rows)):
            sheet.setRowHeight(str(j + 1), int(round(row_h / _PX)))
        last = f"{cols[-1]}{len(rows)}"
        if head_rows:
            sheet.setStyle(f"{cols[0]}1:{cols[-1]}{head_rows}", "bold")
            sheet.setAlignment(f"{cols[0]}1:{cols[-1]}{head_rows}", "center")
        if len(rows) > head_rows and len(cols) > 1:
            sheet.setAlignment(f"{cols[1]}{head_rows + 1}:{last}", "right")
        return f"{cols[0]}1", last

    def drawn_table(self, name, rows, widths, row_h, size, left, top, head_rows, span_first=False):
        """A table on the page: its grid as a symbol and each cell's text as an annotation (text the
        PDF keeps as text; a spreadsheet view's cells become outlines in it). Centred texts; header rows
        bold; span_first: the first row is one cell."""
        w, h = sum(widths), row_h * len(rows)
        px = 1.0 / _PX
        thin, thick = 0.18 * px, 0.35 * px
        xs = np.concatenate([[0.0], np.cumsum(widths)])
        lines = [f'<rect x="0" y="0" width="{w * px:.3f}" height="{h * px:.3f}" '
                 f'style="fill:none;stroke:#000000;stroke-width:{thick:.3f}"/>']
        for j in range(1, len(rows)):
            width = thick if j == head_rows else thin
            lines.append(f'<path d="M0,{j * row_h * px:.3f} H{w * px:.3f}" '
                         f'style="fill:none;stroke:#000000;stroke-width:{width:.3f}"/>')
        for i in range(1, len(widths)):
            y0 = row_h * px if span_first else 0.0
            lines.append(f'<path d="M{xs[i] * px:.3f},{y0:.3f} V{h * px:.3f}" '
                         f'style="fill:none;stroke:#000000;stroke-width:{thin:.3f}"/>')
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w * px:.3f}" '
               f'height="{h * px:.3f}" viewBox="0 0 {w * px:.3f} {h * px:.3f}">\n' + "\n".join(lines) + "\n</svg>\n")
        grid = self.add("TechDraw::DrawViewSymbol", name, name)
        self.page.addView(grid)
        grid.Symbol = svg
        grid.X, grid.Y = left + w / 2.0, top - h / 2.0
        for j, row in enumerate(rows):
            y = top - (j + 0.5) * row_h
            for i, text in enumerate(row):
                if not text:
                    continue
                x = left + (w / 2.0 if span_first and j == 0 else (xs[i] + xs[i + 1]) / 2.0)
                self.annotation(f"{name}Cell", [text], x, y, size, "Bold" if j < head_rows else "Normal")
        return w, h

    def info_table(self, corner):
        """Template data, its upper right corner at `corner`; returns the table's lower left corner."""
        info = _template_info(self.guide, self.date)
        self.info_sheet = self.add("Spreadsheet::Sheet", "DrawingTemplateData", f"{self.guide.Label} template data")
        self.group.addObject(self.info_sheet)
        sx, sy, sz = info["size"]
        # Units in the first column: a sheet restored from a file reads "2.50 mm" as a number.
        rows = [["TEMPLATE", ""],
                ["Case", info["case"]],
                ["Thickness (mm)", f"{info['thickness']:.2f}"],
                ["Clearance (mm)", f"{info['clearance']:.2f}"],
                ["Volume (mm³)", f"{info['volume']:.1f}"],
                ["Size X × Y × Z (mm)", f"{sx:.1f} × {sy:.1f} × {sz:.1f}"],
                ["Sleeves", str(info["sleeves"])],
                ["Date", info["date"]]]
        size = self.small + 0.5
        widths = [_text_width(max((r[i] for r in rows), key=len), size) + 2.0 * size for i in range(2)]
        row_h = 2.0 * size
        self.sheet_table(self.info_sheet, 0, rows, 1, widths, size, row_h)
        self.info_sheet.mergeCells("A1:B1")
        w, h = sum(widths), row_h * len(rows)
        self.drawn_table("TemplateTable", rows, widths, row_h, size, corner[0] - w, corner[1], 1, span_first=True)
        return corner[0] - w, corner[1] - h

    def sleeve_table(self, region):
        x0, y0, x1, y1 = region
        self.sheet = self.add("Spreadsheet::Sheet", "DrawingSleeveTable", f"{self.guide.Label} sleeve table")
        self.group.addObject(self.sheet)
        head = ["Sleeve", "Entry X", "Entry Y", "Entry Z", "Azimuth", "Elevation", "Ø inner", "Ø outer",
                "Length", "Offset", "Top to entry", "Depth"]
        units = ["", "mm", "mm", "mm", "°", "°", "mm", "mm", "mm", "mm", "mm", "mm"]
        rows = [head, units]
        for r in sleeve_rows(self.guide):
            rows.append([r["name"], *(f"{c:.2f}" for c in r["entry"]), f"{r['azimuth']:.1f}", f"{r['elevation']:.1f}",
                         f"{r['inner_diameter']:.2f}", f"{r['outer_diameter']:.2f}", f"{r['length']:.2f}",
                         f"{r['offset']:.2f}", f"{r['depth_to_entry']:.2f}",
                         f"{r['depth']:.2f}" if r["depth"] > 0 else "-"])
        notes = ["Direction of drilling, into the bone: azimuth in the XY plane from +X toward +Y, elevation "
                 "from the XY plane toward +Z.",
                 "Top to entry = offset + length: drill travel from the sleeve top to the bone. Depth: planned "
                 "depth into the bone. Drill: Ø inner."]
        size = self.small
        note_h = 2 * 1.6 * size + 2.0
        row_h = 2.0 * size
        widths = [_text_width(max((r[i] for r in rows), key=len), size) + 1.6 * size for i in range(len(head))]
        # Shrink to the room: the table and its notes.
        shrink = min(1.0, (x1 - x0) / sum(widths), (y1 - y0 - note_h) / (row_h * len(rows)),
                     (x1 - x0) / _text_width(max(notes, key=len), size))
        size, row_h, widths = size * shrink, row_h * shrink, [w * shrink for w in widths]
        self.sheet_table(self.sheet, 0, rows, 2, widths, size, row_h)
        w, h = self.drawn_table("SleeveTable", rows, widths, row_h, size, x0, y1, 2)
        self.notes = self.annotation("SleeveTableNotes", notes, x0 + (x1 - x0) / 2.0, y1 - h - note_h / 2.0,
                                     size * 0.9)
        self.notes.MaxWidth = x1 - x0


def _seam_side(tube, axis):
    """A unit vector across the axis towards the seam of the sleeve's cylinders. TechDraw 0.20 draws
    a seam as an edge, so the details look across it: the seam then lies on the outline."""
    entry = _vec(tube.Entry)
    for e in tube.Shape.Edges:
        if isinstance(e.Curve, Part.Line):
            w = _vec(e.Vertexes[0].Point) - entry
            w -= (w @ axis) * axis
            if np.linalg.norm(w) > 1e-6:
                return w / np.linalg.norm(w)
    w = np.cross(axis, [0.0, 0.0, 1.0])
    if np.linalg.norm(w) < 0.1:
        w = np.cross(axis, [1.0, 0.0, 0.0])
    return w / np.linalg.norm(w)


def _length(q):
    return float(getattr(q, "Value", q))


def _column(i):
    """Spreadsheet column name of index i (0 -> A)."""
    name = ""
    i += 1
    while i:
        i, k = divmod(i - 1, 26)
        name = chr(ord("A") + k) + name
    return name


def _text_box(text, size, x, y):
    """Page box of a one-line annotation centred at (x, y)."""
    w = _text_width(text, size) / 2.0
    return x - w, y - 0.7 * size, x + w, y + 0.7 * size


def _projected_half_size(shape, d, x):
    """Half width and height of a shape's box seen along d with x to the right."""
    d, x = np.asarray(d, dtype=float), np.asarray(x, dtype=float)
    frame = np.stack([x, np.cross(d, x)])
    b = shape.BoundBox
    corners = np.array([[px, py, pz] for px in (b.XMin, b.XMax) for py in (b.YMin, b.YMax)
                        for pz in (b.ZMin, b.ZMax)]) @ frame.T
    return (corners.max(axis=0) - corners.min(axis=0)) / 2.0


def _text_width(text, size):
    """Width estimate of a text in osifont (TechDraw's default), mm."""
    return 0.62 * size * len(text)


def _view_edges(view):
    """(index, edge) of all edges of a recomputed DrawViewPart, visible ones first (as 'EdgeN' counts)."""
    count = len(view.getVisibleEdges()) + len(view.getHiddenEdges())
    return [(i, view.getEdgeByIndex(i)) for i in range(count)]


# ---------------------------------------------------------------------------------------------
# Export


def _style(page):
    """Line widths and text sizes of the page's view providers (GUI only). FreeCAD 0.20.2 as Debian
    builds it draws every edge of a DrawViewPart as a hairline whatever its LineWidth (its line scale
    factor is 0), so the dimensions are thin too, for an even drawing."""
    for v in page.Views:
        vo = getattr(v, "ViewObject", None)
        if vo is None:
            continue
        settings = {}
        if v.isDerivedFrom("TechDraw::DrawViewDimension"):
            settings = {"Fontsize": 3.0, "Arrowsize": 2.5, "LineWidth": 0.13}
            # Short dimensions: arrows outside, pointing in, so that the text stands clear.
            view = v.References2D[0][0] if v.References2D else None
            if view is not None and v.getRawValue() * view.Scale < 5.0 * settings["Fontsize"]:
                settings["FlipArrowheads"] = True
        elif v.isDerivedFrom("TechDraw::DrawViewPart"):
            settings = {"LineWidth": 0.35, "HiddenWidth": 0.18, "ExtraWidth": 0.18}
        for key, value in settings.items():
            if key in vo.PropertiesList:
                setattr(vo, key, value)


_GENERAL = "User parameter:BaseApp/Preferences/Mod/TechDraw/General"


def _export_here(page, pdf, svg):
    """Exports the page with FreeCAD's GUI in this process."""
    import FreeCADGui as Gui
    import TechDrawGui

    # TechDraw 0.20 draws hidden lines solid unless a preference says dashed, and reads it when it
    # draws: set it for this export only.
    prefs = App.ParamGet(_GENERAL)
    had = "HiddenLine" in prefs.GetInts()
    old = prefs.GetInt("HiddenLine", 0)
    prefs.SetInt("HiddenLine", 1)
    try:
        page.ViewObject.show()
        Gui.updateGui()
        _style(page)
        for v in page.Views:
            v.touch()
        page.Document.recompute()
        Gui.updateGui()
        if pdf:
            TechDrawGui.exportPageAsPdf(page, pdf)
        if svg:
            TechDrawGui.exportPageAsSvg(page, svg)
    finally:
        if had:
            prefs.SetInt("HiddenLine", old)
        else:
            prefs.RemInt("HiddenLine")


_SESSION = """# Exports one TechDraw page with FreeCAD's GUI: written by st_drawing.py, run under Xvfb.
import sys
sys.path.insert(0, {here!r})
import st_drawing
st_drawing._gui_session()
"""


def _gui_session():
    """Runs inside FreeCAD's GUI (see _export_subprocess): opens the document, exports the page,
    writes a status file, quits. Arguments come in environment variables."""
    import FreeCADGui as Gui
    from PySide import QtCore

    env = os.environ

    def work():
        status = {"ok": False}
        try:
            import st_features  # noqa: F401  (restores the workbench's objects from outside a Mod folder too)
            doc = App.openDocument(env["ST_DRAWING_DOC"])
            page = doc.getObject(env["ST_DRAWING_PAGE"])
            if page is None:
                raise RuntimeError(f"no page {env['ST_DRAWING_PAGE']} in {env['ST_DRAWING_DOC']}")
            _export_here(page, env.get("ST_DRAWING_PDF"), env.get("ST_DRAWING_SVG"))
            status["ok"] = True
        except Exception:
            status["error"] = traceback.format_exc()
        finally:
            with open(env["ST_DRAWING_STATUS"], "w") as f:
                json.dump(status, f)
            for name in list(App.listDocuments()):
                App.closeDocument(name)
            QtCore.QTimer.singleShot(0, Gui.getMainWindow().close)

    QtCore.QTimer.singleShot(200, work)


def _export_subprocess(doc, page, pdf, svg):
    """Exports the page from a saved copy of the document with FreeCAD's GUI under Xvfb."""
    freecad, xvfb = shutil.which("freecad"), shutil.which("xvfb-run")
    if not freecad or not xvfb:
        missing = " and ".join(n for n, p in (("freecad", freecad), ("xvfb-run", xvfb)) if not p)
        raise RuntimeError(f"{page.Label}: exporting PDF/SVG without FreeCAD's GUI needs {missing} on the PATH "
                           "(Debian packages freecad and xvfb)")
    with tempfile.TemporaryDirectory(prefix="surgical-template-drawing-") as tmp:
        fcstd = os.path.join(tmp, "drawing.FCStd")
        doc.saveCopy(fcstd)
        script = os.path.join(tmp, "export_page.py")
        with open(script, "w") as f:
            f.write(_SESSION.format(here=_HERE))
        status_path = os.path.join(tmp, "status.json")
        os.makedirs(os.path.join(tmp, "tmp"))
        env = dict(os.environ, QTWEBENGINE_DISABLE_SANDBOX="1", ST_DRAWING_DOC=fcstd, ST_DRAWING_PAGE=page.Name,
                   ST_DRAWING_PDF=pdf or "", ST_DRAWING_SVG=svg or "", ST_DRAWING_STATUS=status_path,
                   TMPDIR=os.path.join(tmp, "tmp"))   # FreeCAD's recovery files: never a dialog from old ones
        proc = subprocess.Popen([xvfb, "-a", "-s", "-screen 0 1280x1024x24", freecad, script], env=env,
                                stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
        try:
            output, _ = proc.communicate(timeout=EXPORT_TIMEOUT)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            output, _ = proc.communicate()
            raise RuntimeError(f"{page.Label}: FreeCAD's GUI did not export the page within {EXPORT_TIMEOUT} s:\n"
                               f"{output[-2000:]}") from None
        status = {}
        if os.path.exists(status_path):
            with open(status_path) as f:
                status = json.load(f)
        if not status.get("ok"):
            detail = status.get("error") or output[-2000:]
            raise RuntimeError(f"{page.Label}: export with FreeCAD's GUI failed (exit {proc.returncode}):\n{detail}")


def _umask():
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _write_text(path, text):
    tmp = f"{path}.tmp-{os.getpid()}"
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(text)
    os.replace(tmp, path)


def _remove_drawings_of(guide, keep=None):
    """The guide's previous drawing (page, views, lines and tables), all but the page `keep`:
    make_drawing replaces it once the new one has passed its checks."""
    doc = guide.Document
    for page in [o for o in doc.Objects if o.TypeId == "TechDraw::DrawPage"]:
        if getattr(page, "SurgicalGuide", None) != guide.Name or page == keep:
            continue
        names = [v.Name for v in page.Views] + [page.Name]
        if page.Template is not None:
            names.append(page.Template.Name)
        group = doc.getObject(getattr(page, "DrawingData", "") or "")
        if group is not None:
            names += [o.Name for o in group.Group] + [group.Name]
        for name in names:
            if doc.getObject(name) is not None:
                doc.removeObject(name)


def _check_guide(guide):
    label = getattr(guide, "Label", repr(guide))
    if getattr(getattr(guide, "Proxy", None), "kind", None) != "Guide":
        raise ValueError(f"{label}: not a surgical guide")
    doc = guide.Document
    if any("Touched" in o.State for o in [guide, guide.Shell, *guide.Tubes] if o is not None):
        doc.recompute()
    if "Invalid" in guide.State:
        why = getattr(guide, "Status", "") or "see the Report view"
        raise ValueError(f"{label}: the guide failed to recompute ({why})")
    if guide.Shell is None:
        raise ValueError(f"{label}: the guide has no template shell")
    if guide.Mesh.CountFacets == 0:
        raise ValueError(f"{label}: the guide mesh is empty (recompute it first)")
    for tube in guide.Tubes:
        if tube.Shape.isNull() or not tube.Shape.Solids:
            raise ValueError(f"{tube.Label}: the tube has no solid (recompute it first)")


def make_drawing(guide, path, paper="A3", pdf=True, svg=True):
    """The documentation drawing of a guide: a TechDraw page in its document (one undo step, replacing
    the guide's previous drawing) with front, top and side views, a dimensioned detail per sleeve and
    tables of the sleeves and the template; exported to PDF and SVG at `path` with its extension
    replaced, and a drill protocol next to them (.txt). Without the GUI the export runs FreeCAD under
    Xvfb in a subprocess. Returns {"page", "pdf", "svg", "protocol" (the text), "protocol_path"}."""
    _check_guide(guide)
    spec = _paper(paper)
    doc = guide.Document
    base = os.path.splitext(os.path.abspath(os.fspath(path)))[0]
    folder = os.path.dirname(base)
    os.makedirs(folder, exist_ok=True)
    date = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    protocol = drill_protocol(guide, date)
    builder = _Builder(doc, guide, spec, date)
    builder.arrays = st_bridge.mesh_to_arrays(guide.Mesh)
    doc.openTransaction("Make drawing")
    try:
        page = builder.build()
        doc.recompute()
        builder.dimension_details()
        doc.recompute()
        _check_page(builder)
        _remove_drawings_of(guide, keep=page)  # only now: a failure above keeps the old drawing
        doc.commitTransaction()
    except Exception:
        doc.abortTransaction()
        builder.remove_created()
        raise
    out = {"page": page, "pdf": None, "svg": None, "protocol": protocol, "protocol_path": base + ".txt"}
    targets = {k: base + "." + k for k, wanted in (("pdf", pdf), ("svg", svg)) if wanted}
    if targets:
        temps = {k: tempfile.mkstemp(dir=folder, prefix=".drawing-", suffix="." + k) for k in targets}
        for fd, _ in temps.values():
            os.close(fd)
        try:
            tmp = {k: p for k, (_, p) in temps.items()}
            if App.GuiUp:
                _export_here(page, tmp.get("pdf"), tmp.get("svg"))
            else:
                _export_subprocess(doc, page, tmp.get("pdf"), tmp.get("svg"))
            for k, p in tmp.items():
                if os.path.getsize(p) == 0:
                    raise RuntimeError(f"{page.Label}: the {k.upper()} export wrote nothing")
            mode = 0o666 & ~_umask()
            for k, p in tmp.items():
                os.chmod(p, mode)
                os.replace(p, targets[k])
                out[k] = targets[k]
        finally:
            for _, p in temps.values():
                if os.path.exists(p):
                    os.remove(p)
    _write_text(base + ".txt", protocol)
    return out


def _check_page(builder):
    """Every view computed, every dimension measuring what it documents."""
    for v in builder.page.Views:
        if "Invalid" in v.State:
            raise RuntimeError(f"{v.Label}: TechDraw failed on this view")
    for r, tube in zip(sleeve_rows(builder.guide), builder.guide.Tubes):
        want = (r["length"], r["outer_diameter"], r["inner_diameter"])
        got = tuple(d.getRawValue() for d in builder.dimensions.get(tube.Name, ()))
        if len(got) != 3 or any(abs(a - b) > 1e-4 for a, b in zip(want, got)):
            raise RuntimeError(f"{tube.Label}: sleeve dimensions {got} do not match {want}")

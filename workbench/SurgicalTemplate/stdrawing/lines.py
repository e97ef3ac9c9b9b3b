"""Line drawings of a guide mesh for the drawing's views (guide_lines).

TechDraw projects a mesh turned into a Part shape as every triangle edge (a black smear). So the views
draw line drawings computed here from the mesh: its outlines (the contour where the smoothed surface
turns away from the viewer, interpolated inside the triangles so that the lines are smooth), its sharp
edges (creases of more than CREASE_ANGLE), and the sleeves from their exact definition (cylinder
outlines as lines, the top rims as circles and arcs); hidden parts removed by casting rays through the
mesh with the kernel. These 3D edges become the Shape of one Part::Feature per view.
"""
import math

import numpy as np

import FreeCAD as App
import Part

import st_bridge
from stdrawing.protocol import vec

CREASE_ANGLE = 40.0   # degrees between face normals above which an edge of the mesh is drawn


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
        self.axis = vec(tube.Direction) / np.linalg.norm(vec(tube.Direction))   # into the bone
        self.entry = vec(tube.Entry)
        self.R, self.r = float(tube.OuterDiameter.Value) / 2.0, float(tube.InnerDiameter.Value) / 2.0
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
            # A loop smaller than the tolerance simplifies to one point twice: nothing to draw.
            p = p[np.concatenate([[True], np.linalg.norm(np.diff(p, axis=0), axis=1) > 1e-7])]
            if len(p) < 2:
                continue
            if len(p) == 2:
                edges.append(Part.LineSegment(App.Vector(*p[0]), App.Vector(*p[1])).toShape())
            else:
                edges.append(Part.makePolygon([App.Vector(*q) for q in p]))
        for s in sleeves:
            edges += s.edges(d, lambda p: caster.occluded(p, d, 0.05 + tol))
        out.append(Part.makeCompound(edges))
    return out

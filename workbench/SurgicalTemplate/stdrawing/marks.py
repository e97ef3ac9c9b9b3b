"""What the drawing's main views carry besides the guide's lines: a numbered balloon on each sleeve, keyed
to the sleeve table (balloons), and an axis marker that ties the view to the scan's coordinates, in which
the tables give every entry and direction (axis_marker). Page positions are in mm, relative to the view's
centre, y up: a view shows the model in the frame (x, d x x) of its Direction d and XDirection x, centred
on the box of its source shape."""
import math

import numpy as np

import FreeCAD as App
import Part

from stdrawing.protocol import sleeve_rows

BALLOON = 0.95        # a balloon's radius in text heights (TechDraw sizes the bubble round its number)
AXIS = 8.0            # mm on the page, the marker's arrows
TURNS = 24            # places tried for a balloon: 8 directions, then twice as many pushed farther out


class ViewFrame:
    """Where model points land in a view: page mm relative to the view's centre."""

    def __init__(self, shape, d, x, scale):
        d, x = np.asarray(d, dtype=float), np.asarray(x, dtype=float)
        self.rows = np.stack([x, np.cross(d, x)])
        self.scale = scale
        b = shape.BoundBox
        corners = _corners(b) @ self.rows.T
        self.centre = (corners.min(axis=0) + corners.max(axis=0)) / 2.0   # TechDraw centres a view on its box

    def page(self, p):
        return (self.rows @ np.asarray(p, dtype=float) - self.centre) * self.scale


def _corners(b):
    return np.array([[px, py, pz] for px in (b.XMin, b.XMax) for py in (b.YMin, b.YMax) for pz in (b.ZMin, b.ZMax)])


def balloons(builder, view, frame, cx, cy):
    """A numbered balloon per sleeve (its row in the sleeve table), its leader from the sleeve's top,
    the bubble outward along the projected axis or, where that would meet another bubble or a sleeve's
    top, turned or pushed out until it meets none: [(balloon, its box on the page)]. TechDraw keeps a
    balloon's position relative to its view's centre, in the view's unscaled mm."""
    rows = sleeve_rows(builder.guide)
    s, text = frame.scale, builder.text
    tops = [frame.page(r["top"]) for r in rows]
    rb = BALLOON * text
    out, centres = [], []
    for number, (r, top) in enumerate(zip(rows, tops), start=1):
        q = -frame.rows @ r["direction"]
        q = q / np.linalg.norm(q) if np.linalg.norm(q) > 0.35 else np.array([0.7071, 0.7071])
        reach = r["outer_diameter"] / 2.0 * s + 2.0 * rb
        at = None
        for k in range(TURNS):
            turn = math.radians(25.0 * ((k % 8 + 1) // 2) * (1 if k % 2 else -1))
            rot = np.array([[math.cos(turn), -math.sin(turn)], [math.sin(turn), math.cos(turn)]])
            p = top + rot @ q * reach * (1.0 + 0.6 * (k // 8))
            if all(np.linalg.norm(p - o) >= 2.2 * rb for o in centres) and \
                    all(np.linalg.norm(p - t) >= rb + 0.5 * text for t in tops):
                at = p
                break
        if at is None:
            at = top + q * reach * 2.8
        b = builder.add("TechDraw::DrawViewBalloon", f"{view.Name}Balloon", f"{view.Label} balloon {number}")
        b.SourceView = view
        b.Text = str(number)
        b.BubbleShape = "Circular"
        b.EndType = "Dot"
        b.OriginX, b.OriginY = float(top[0] / s), float(top[1] / s)
        b.X, b.Y = float(at[0] / s), float(at[1] / s)
        builder.page.addView(b)
        centres.append(at)
        out.append((b, (cx + at[0] - rb, cy + at[1] - rb, cx + at[0] + rb, cy + at[1] + rb)))
    return out


def marker_foot(shape, d, x):
    """Where a view's axis marker stands: the scan's origin when the view shows it, else the corner of
    the shape's box that the view puts at its lower left, rounded outward to whole mm (so that its
    coordinates read cleanly). Returns (point, at_origin)."""
    rows = np.stack([np.asarray(x, dtype=float), np.cross(np.asarray(d, dtype=float), np.asarray(x, dtype=float))])
    b = shape.BoundBox
    lo, hi = np.array([b.XMin, b.YMin, b.ZMin]), np.array([b.XMax, b.YMax, b.ZMax])
    seen = _corners(b) @ rows.T
    if np.all(seen.min(axis=0) <= 0.0) and np.all(0.0 <= seen.max(axis=0)):
        return np.zeros(3), True
    foot = np.floor(lo)
    for k in range(3):
        along = rows[:, k][np.argmax(np.abs(rows[:, k]))]
        if abs(along) > 0.5 and along < 0:
            foot[k] = np.ceil(hi[k])
    return foot, False


def axis_marker(shape, d, x, scale):
    """The view's axis marker as 3D edges to draw with its lines: from its foot (marker_foot) an arrow
    along each scan axis that lies in the view, AXIS mm long on the page. Returns (the shape with the
    marker, [(letter, model point)] for the arrows' names, the foot, at_origin)."""
    d = np.asarray(d, dtype=float)
    foot, at_origin = marker_foot(shape, d, x)
    length = AXIS / scale
    edges, names = [], []
    for k, letter in enumerate("XYZ"):
        axis = np.eye(3)[k]
        if abs(axis @ d) > 0.5:
            continue                                    # seen end on
        tip = foot + axis * length
        side = np.cross(d, axis) * 0.18 * length
        for a, b in ((foot, tip), (tip, tip - axis * 0.3 * length + side), (tip, tip - axis * 0.3 * length - side)):
            edges.append(Part.makeLine(App.Vector(*a), App.Vector(*b)))
        names.append((letter, foot + axis * length * 1.3))
    return Part.makeCompound([shape, *edges]), names, foot, at_origin


def axis_labels(builder, view_name, frame, names, foot, at_origin, cx, cy):
    """The arrows' letters and, under the foot, its scan coordinates: [(annotation, its box)]."""
    text = builder.small
    out = []
    for letter, p in names:
        u, v = frame.page(p)
        a = builder.annotation(f"{view_name}Axis{letter}", [letter], cx + u, cy + v - 0.35 * text, text, "Bold")
        out.append((a, (cx + u - 0.5 * text, cy + v - 0.6 * text, cx + u + 0.5 * text, cy + v + 0.6 * text)))
    words = "scan origin (0, 0, 0)" if at_origin else "(" + ", ".join(f"{c:g}" for c in foot) + ")"
    u, v = frame.page(foot)
    w = 0.62 * text * len(words)
    y = cy + v - 1.4 * text
    a = builder.annotation(f"{view_name}AxisFoot", [words], cx + u, y, text)
    out.append((a, (cx + u - w / 2.0, y - 0.7 * text, cx + u + w / 2.0, y + 0.7 * text)))
    return out

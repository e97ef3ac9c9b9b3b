"""The thickness map's colour bar, as FreeCAD's Inspection feature shows one: the colours of
stfunctions.inspection.thickness_colour from the bone (red: in it) through the seat (green) to the outer
surface (blue) and beyond (grey: sleeves and housings), with the distances in mm beside it; and what a
click on the coloured mesh reads (MapReader)."""
import FreeCAD as App
from PySide import QtCore, QtGui

from stfunctions.inspection import thickness_colour


def bar_stops(thickness, clearance):
    """(distance in mm, label) of the bar's ticks, from the bone outward."""
    c, t = clearance, thickness
    return [(-0.25 * t, "in the bone"), (c, f"{c:.2f} mm seated"), (c + t / 2, f"{c + t / 2:.2f} mm"),
            (c + t, f"{c + t:.2f} mm outer surface"), (c + 1.4 * t, "beyond: sleeves")]


class ColourBar(QtGui.QWidget):
    """A vertical bar from the most distant colour (top) down to the bone (bottom), each distance's
    colour on its row, the ticks' distances beside it."""

    def __init__(self, thickness, clearance, parent=None):
        super().__init__(parent)
        self.thickness, self.clearance = thickness, clearance
        self.stops = bar_stops(thickness, clearance)
        self.setMinimumSize(200, 150)

    def distance_at(self, fraction):
        """The distance a fraction of the bar's height (0: bottom) stands for."""
        lo, hi = self.stops[0][0], self.stops[-1][0]
        return lo + (hi - lo) * fraction

    def paintEvent(self, event):
        p = QtGui.QPainter(self)
        h, bar = self.height() - 12, 22
        top = 6
        for row in range(h):
            r, g, b = thickness_colour(self.distance_at(1.0 - row / max(h - 1, 1)), self.thickness, self.clearance)
            p.setPen(QtGui.QColor.fromRgbF(r, g, b))
            p.drawLine(4, top + row, 4 + bar, top + row)
        p.setPen(self.palette().color(QtGui.QPalette.WindowText))
        p.drawRect(4, top, bar, h - 1)
        lo, hi = self.stops[0][0], self.stops[-1][0]
        metrics = p.fontMetrics()
        for distance, text in self.stops:
            y = top + int(round((1.0 - (distance - lo) / (hi - lo)) * (h - 1)))
            p.drawLine(4 + bar, y, 10 + bar, y)
            p.drawText(14 + bar, y + metrics.ascent() // 2 - 1, text)
        p.end()


class MapReader:
    """Reads the map where the user clicks the inspected object in the 3D view: the facet under the
    cursor and its distance from the bone, in the panel's label and the Report view."""

    def __init__(self, view, obj, distances, label):
        self.view, self.obj, self.distances, self.label = view, obj, distances, label
        self.callback = view.addEventCallback("SoMouseButtonEvent", self.on_mouse)
        self.last = None

    def on_mouse(self, info):
        if info.get("State") == "DOWN" and info.get("Button") == "BUTTON1":
            self.read(info["Position"])

    def read(self, position):
        """The reading at a screen position, or None off the object: (facet, point, distance)."""
        hit = self.view.getObjectInfo(tuple(position))
        if not hit or hit.get("Object") != self.obj.Name:
            return None
        p = App.Vector(hit["x"], hit["y"], hit["z"])
        d = App.Vector(self.view.getViewDirection())
        facets = self.obj.Mesh.nearestFacetOnRay(tuple(p - d * 0.05), tuple(d))
        if not facets:
            return None
        facet = int(list(facets)[0])
        distance = self.distances[facet]
        self.last = (facet, (p.x, p.y, p.z), distance)
        where = "in the bone" if distance < 0 else "from the bone"
        text = f"({p.x:.2f}, {p.y:.2f}, {p.z:.2f}): {abs(distance):.2f} mm {where}"
        self.label.setText(text)
        App.Console.PrintMessage(f"Surgical Template: {self.obj.Label} at {text}\n")
        return self.last

    def stop(self):
        if self.callback is not None:
            self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
            self.callback = None

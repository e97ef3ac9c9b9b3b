"""The boundary task panel: control points of a boundary on the bone, clicked, dragged, inserted and
deleted in the 3D view with the curve through them shown live (its drawing and mouse and keys are in
boundary_view); OK creates the boundary or writes the edited points back, recorded and undoable.
Its form is Resources/ui/boundary.ui."""
import FreeCAD as App
import FreeCADGui as Gui
import Part
from PySide import QtGui

from stobjects.boundary import Boundary
from sttaskpanels.boundary_view import Overlay, PanelEvents
from stutils.gui_utils import leave_edit, load_form, ref, run, view_of


def edit_boundary(boundary):
    """Opens the boundary panel on the points of an existing boundary; OK writes them back as one undo
    step. Its view provider's edit mode calls this (double-click in the tree, or
    Gui.getDocument(...).setEdit(name)). False when it cannot open."""
    if boundary.Bone is None:
        App.Console.PrintError(f"Surgical Template: '{boundary.Label}' has no bone to edit its points on\n")
        return False
    if Gui.Control.activeDialog():
        App.Console.PrintWarning("Surgical Template: close the open task panel first, then edit the boundary\n")
        return False
    Gui.Control.showDialog(BoundaryPanel(boundary.Bone, boundary))
    return True


def _rounded(points):
    return [(round(p.x, 4), round(p.y, 4), round(p.z, 4)) for p in points]


def _pixels(a, b):
    return ((a[0] - b[0]) ** 2 + (a[1] - b[1]) ** 2) ** 0.5


class _Preview:
    """The curve the panel shows, as a shape (a closed wire); it lives in the 3D view only."""

    def __init__(self, curve):
        self.Shape = Part.makePolygon(curve + curve[:1])


class BoundaryPanel:
    """Control points of a boundary on the bone, drawn anew or edited; the curve through them is shown as
    it is computed. OK creates the boundary, or writes the edited points back, as one undo step.

    In the 3D view (the panel's text says the same):
      click on the bone   adds a point: after the selected point; else, with "Insert into nearest segment",
                          between the two points whose segment of the loop it is nearest to; else at the end
      drag a point        moves it: press within PICK_PIXELS of it, release on the bone (released off the
                          bone, or Esc, it goes back)
      click a point       selects it (highlighted); Ctrl+click on the bone then moves it there
      Delete              removes the selected points (list or 3D view); Ctrl+Z undoes the panel's last
                          change; Enter is OK
    Scripts and tests drive the same steps, with screen positions as the view reports them (click, press,
    drag, release, move_selected_to) or with points (insert_at, move, delete, select, undo).
    """

    last = None  # the open panel, for scripts and tests
    PICK_PIXELS = 10  # how near (screen pixels) a press must be to a control point to drag it

    def __init__(self, bone, boundary=None):
        BoundaryPanel.last = self
        self.bone, self.boundary = bone, boundary
        self.points = [App.Vector(p) for p in boundary.Points] if boundary is not None else []
        self.history = []  # the point lists before each change, for Undo
        self.dragging = None  # {index, from, press, moved} while a point is dragged
        self.curve, self.error, self.preview = [], "", None
        self.done = False
        self.form = load_form("boundary")
        if boundary is not None:
            self.form.setWindowTitle("Edit boundary")
        where = f"'{boundary.Label}' on '{bone.Label}'" if boundary is not None else f"'{bone.Label}'"
        self.form.text.setText(f"Points around the region on {where}, in order. Click on the bone: add a point "
                               "(after the selected one). Drag a point: move it. Click a point: select it; "
                               "Ctrl+click on the bone: move the selected point there. Delete: remove the "
                               "selected points; Ctrl+Z: undo. Enter: OK.")
        self.nearest = self.form.nearest
        self.nearest.setChecked(boundary is not None)
        self.list = self.form.points
        self.list.itemSelectionChanged.connect(self.redraw)
        self.form.remove.clicked.connect(self.remove_selected)
        self.form.undo.clicked.connect(self.undo)
        self.form.clear.clicked.connect(self.clear)
        self.status = self.form.status
        self.view = view_of(bone.Document)
        self.overlay = Overlay(self.view)
        self.events = PanelEvents(self)
        self.update()

    # Where things are on screen.
    def hit(self, position):
        """Where the view ray at a screen position first meets the bone, or None. Whatever lies in front
        of the bone (template, guide, the curve) is looked through."""
        try:
            hits = self.view.getObjectsInfo((int(position[0]), int(position[1]))) or []
        except Exception:
            return None
        doc = self.bone.Document.Name
        for h in hits:
            if h.get("Object") == self.bone.Name and h.get("Document", doc) == doc:
                return App.Vector(h["x"], h["y"], h["z"])
        return None

    def point_at(self, position):
        """The control point within PICK_PIXELS of a screen position (the nearest one), or None; a point
        hidden behind the bone from this side does not count."""
        near = []
        for i, p in enumerate(self.points):
            d = _pixels(self.view.getPointOnScreen(p), position)
            if d <= self.PICK_PIXELS:
                near.append((d, i))
        if not near:
            return None
        front = self.hit(position)
        into = App.Vector(self.view.getViewDirection())
        tolerance = max(1.0, 0.02 * self.bone.Mesh.BoundBox.DiagonalLength)
        for _, i in sorted(near):
            if front is None or (self.points[i] - front).dot(into) <= tolerance:
                return i
        return None

    def insert_index(self, point):
        """Where a new point goes: after the (last) selected point; else, with the nearest-segment option
        and 3 points or more, into the loop's segment nearest to it (the loop closes last -> first);
        else at the end."""
        rows = self.selected_rows()
        if rows:
            return rows[-1] + 1
        n = len(self.points)
        if n < 3 or not self.nearest.isChecked():
            return n

        def distance(i):
            a, b = self.points[i], self.points[(i + 1) % n]
            ab = b - a
            t = 0.0 if ab.Length == 0 else max(0.0, min(1.0, (point - a).dot(ab) / ab.dot(ab)))
            return (a + ab * t - point).Length

        return min(range(n), key=distance) + 1

    # Changes of the points.
    def change(self, points, select=None):
        """Every change goes here: the previous points kept for Undo, then list, curve and markers."""
        self.history.append(list(self.points))
        self.points = points
        self.update(select)

    def insert_at(self, point, index=None):
        """Adds a point (mm) at index, or where insert_index puts it; returns its index. Inserted after a
        selected point, the new one becomes the selected one, so clicks continue from it."""
        point = App.Vector(*point) if isinstance(point, (tuple, list)) else App.Vector(point)
        follow = bool(self.selected_rows())
        if index is None:
            index = self.insert_index(point)
        points = list(self.points)
        points.insert(index, point)
        self.change(points, [index] if follow else [])
        return index

    def move(self, index, point):
        point = App.Vector(*point) if isinstance(point, (tuple, list)) else App.Vector(point)
        points = list(self.points)
        points[index] = point
        self.change(points)

    def delete(self, *indices):
        drop = {i % len(self.points) for i in indices} if self.points else set()
        if drop:
            self.change([p for i, p in enumerate(self.points) if i not in drop], [])

    def remove_selected(self):
        self.delete(*self.selected_rows())

    def clear(self):
        if self.points:
            self.change([], [])

    def undo(self):
        """Takes back the last change of the points (the document is not touched)."""
        if not self.history:
            return False
        self.points = self.history.pop()
        self.update([])
        return True

    def selected_rows(self):
        return sorted(self.list.row(item) for item in self.list.selectedItems())

    def select(self, *indices):
        self.list.blockSignals(True)
        self.list.clearSelection()
        for i in indices:
            self.list.item(i).setSelected(True)
        self.list.blockSignals(False)
        self.redraw()

    # Gestures, at screen positions as the view reports them (getPointOnScreen, event positions).
    def click(self, position):
        """A click at a screen position: a point where it meets the bone, placed by insert_index."""
        p = self.hit(position)
        if p is None:
            return False
        self.insert_at(p)
        return True

    def move_selected_to(self, position):
        """Ctrl+click: the selected point moves to where the screen position meets the bone."""
        rows, p = self.selected_rows(), self.hit(position)
        if len(rows) != 1 or p is None:
            self.status.setText("Ctrl+click on the bone moves the selected point: select one point first"
                                if len(rows) != 1 else "Ctrl+click: that is not on the bone")
            return False
        self.move(rows[0], p)
        return True

    def press(self, position):
        """Mouse press: near a visible control point it starts dragging that point (True)."""
        i = self.point_at(position)
        if i is None:
            return False
        self.dragging = {"index": i, "from": App.Vector(self.points[i]), "press": tuple(position), "moved": False}
        self.redraw()
        return True

    def drag(self, position):
        """Mouse motion while dragging: the point follows over the bone and the curve with it."""
        d = self.dragging
        if d is None:
            return False
        if not d["moved"] and _pixels(position, d["press"]) < 3:
            return True
        p = self.hit(position)
        if p is None:
            return False
        d["moved"] = True
        self.points[d["index"]] = p
        self.update()
        return True

    def release(self, position):
        """Mouse release ends a drag: on the bone the point moves there (one change for Undo); off the
        bone it goes back. Without motion it was a click on the point: it is selected (or deselected)."""
        d, self.dragging = self.dragging, None
        if d is None:
            return False
        i = d["index"]
        self.points[i] = d["from"]
        if not d["moved"] and _pixels(position, d["press"]) < 3:
            self.update([] if self.selected_rows() == [i] else [i])
            return True
        p = self.hit(position)
        if p is None:
            self.update()
            return False
        self.move(i, p)
        return True

    def cancel_drag(self):
        if self.dragging is not None:
            self.points[self.dragging["index"]] = self.dragging["from"]
            self.dragging = None
            self.update()

    # Showing.
    def update(self, select=None):
        """The list, the curve (traced as the boundary will be) and the markers, after a change."""
        rows = self.selected_rows() if select is None else select
        self.list.blockSignals(True)
        self.list.clear()
        for i, p in enumerate(self.points):
            self.list.addItem(f"{i + 1}: {p.x:.2f}, {p.y:.2f}, {p.z:.2f}")
        for r in rows:
            if 0 <= r < self.list.count():
                self.list.item(r).setSelected(True)
        self.list.blockSignals(False)
        self.curve, self.error, self.preview = [], "", None
        if len(self.points) < 3:
            self.status.setText(f"{len(self.points)} point(s): at least 3 needed")
        else:
            try:
                self.curve = Boundary.curve(self.bone, self.points)
                self.preview = _Preview(self.curve)
                self.status.setText(f"{len(self.points)} points; curve {self.preview.Shape.Length:.1f} mm")
            except Exception as e:  # the kernel names what is wrong with the points
                self.curve, self.preview, self.error = [], None, str(e)
                self.status.setText(f"no curve: {e}")
        self.redraw()

    def redraw(self):
        if self.done:
            return
        marked = set(self.selected_rows())
        if self.dragging is not None:
            marked.add(self.dragging["index"])
        self.overlay.show(self.points, self.curve, sorted(marked))

    # Closing.
    def finish(self):
        """Leaves the view as it was: event filters off, curve and markers removed. Every way out of the
        panel (OK, Cancel, the edit mode ended from outside) comes here; the document never held them."""
        if self.done:
            return
        self.done = True
        self.dragging = None
        self.events.unwatch()
        self.overlay.remove()

    def accept(self):
        if self.boundary is not None:
            return self.accept_edit()
        points = _rounded(self.points)
        self.finish()
        Gui.Control.closeDialog()
        if len(points) >= 3:
            run("Create boundary", f"SurgicalTemplate.make_boundary({ref(self.bone)}, {points})\n"
                                   "App.ActiveDocument.recompute()")
        return True

    def accept_edit(self):
        """OK on an existing boundary: Points set through Gui.doCommand (recorded) as one undo step; if the
        boundary cannot be computed from them, the step is rolled back and the document keeps its state."""
        if len(self.points) < 3 or self.error:
            self.status.setText("Not written: " + (self.error or "a boundary needs at least 3 points") +
                                ". Change the points, or Cancel.")
            return False
        b, points = self.boundary, _rounded(self.points)
        self.finish()
        Gui.Control.closeDialog()
        self.leave_edit()
        try:
            doc, unchanged = b.Document, points == _rounded(b.Points)
        except Exception:  # the boundary was deleted while the panel was open
            return True
        if unchanged:
            return True
        doc.openTransaction("Edit boundary")
        ok = run("Edit boundary", f"{ref(b)}.Points = {points}\nApp.getDocument({doc.Name!r}).recompute()")
        if ok and "Invalid" in b.State:
            ok = False
            App.Console.PrintError(f"Surgical Template: Edit boundary failed: '{b.Label}' cannot be computed "
                                   "from the new points; it keeps the old ones\n")
            QtGui.QMessageBox.warning(Gui.getMainWindow(), "Surgical Template",
                                      f"'{b.Label}' cannot be computed from the new points; it keeps the old ones.")
        if ok:
            doc.commitTransaction()
        else:
            doc.abortTransaction()
            doc.recompute()
        return True

    def reject(self):
        self.finish()
        Gui.Control.closeDialog()
        self.leave_edit()
        return True

    def leave_edit(self):
        """Ends the boundary's edit mode, if the panel was opened by it."""
        leave_edit(self.boundary)

    @classmethod
    def edit_ended(cls, boundary):
        """The boundary's edit mode ended from outside the panel (another edit, the document closing):
        the panel closes as if cancelled."""
        p = cls.last
        if p is None or p.done or p.boundary is None:
            return
        try:
            same = (p.boundary.Document.Name, p.boundary.Name) == (boundary.Document.Name, boundary.Name)
        except Exception:
            same = True
        if same:
            p.finish()
            Gui.Control.closeDialog()

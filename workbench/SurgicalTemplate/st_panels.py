"""The workbench's task panels: the boundary panel (click, drag, insert and delete control points on
the bone with the curve shown live), the drilling tube panel (entry by a click, direction from the
surface, the view or a second point, sizes from a sleeve preset) and the Validate panel (inspection
and thickness map). Changes go through st_gui.run, so they are recorded and undoable."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from st_gui import _view_of, preference, ref, run

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
        import Part
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
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Edit boundary" if boundary is not None else "Boundary")
        layout = QtGui.QVBoxLayout(self.form)
        where = f"'{boundary.Label}' on '{bone.Label}'" if boundary is not None else f"'{bone.Label}'"
        text = QtGui.QLabel(f"Points around the region on {where}, in order. Click on the bone: add a point "
                            "(after the selected one). Drag a point: move it. Click a point: select it; "
                            "Ctrl+click on the bone: move the selected point there. Delete: remove the "
                            "selected points; Ctrl+Z: undo. Enter: OK.")
        text.setWordWrap(True)
        layout.addWidget(text)
        self.nearest = QtGui.QCheckBox("Insert into nearest segment")
        self.nearest.setToolTip("With no point selected, a click adds its point between the two neighbours "
                                "whose segment of the loop it is nearest to; unchecked: at the end")
        self.nearest.setChecked(boundary is not None)
        layout.addWidget(self.nearest)
        self.list = QtGui.QListWidget()
        self.list.setSelectionMode(QtGui.QAbstractItemView.ExtendedSelection)
        self.list.itemSelectionChanged.connect(self.redraw)
        layout.addWidget(self.list)
        row = QtGui.QHBoxLayout()
        for label, slot, tip in (("Remove selected", self.remove_selected, "Remove the selected points (Delete)"),
                                 ("Undo", self.undo, "Undo the last change of the points (Ctrl+Z)"),
                                 ("Clear", self.clear, "Remove all points")):
            button = QtGui.QPushButton(label)
            button.setToolTip(tip)
            button.clicked.connect(slot)
            row.addWidget(button)
        layout.addLayout(row)
        self.status = QtGui.QLabel("")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        self.view = _view_of(bone.Document)
        self.overlay = _Overlay(self.view)
        self.events = _PanelEvents(self)
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
            import st_features
            try:
                self.curve = st_features.Boundary.curve(self.bone, self.points)
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
        if self.boundary is None:
            return
        try:
            gui_doc = Gui.getDocument(self.boundary.Document.Name)
            vp = gui_doc.getInEdit()
            if vp is not None and vp.Object.Name == self.boundary.Name:
                gui_doc.resetEdit()
        except Exception:  # document or boundary gone
            pass

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


class _Overlay:
    """What the boundary panel draws over the 3D view: the curve, and the control points as markers
    numbered in loop order, the selected (or dragged) ones highlighted. Coin nodes drawn on top of the
    scene and not pickable, so clicks reach the bone; never document objects, so they leave nothing in
    the undo history or a saved file, and removing the root node cleans up."""

    CURVE = (0.85, 0.10, 0.55)
    POINT = (1.00, 0.45, 0.00)
    SELECTED = (0.00, 0.75, 0.25)
    TEXT = (0.10, 0.10, 0.40)

    def __init__(self, view):
        from pivy import coin
        self.coin, self.view = coin, view
        self.root = coin.SoAnnotation()
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        light = coin.SoLightModel()
        light.model = coin.SoLightModel.BASE_COLOR
        self.root.addChild(pick)
        self.root.addChild(light)
        self.curve = self._layer(coin.SoLineSet(), self.CURVE, line_width=3)
        self.points = self._layer(self._markers(coin.SoMarkerSet.CIRCLE_FILLED_7_7), self.POINT)
        self.marked = self._layer(self._markers(coin.SoMarkerSet.CIRCLE_FILLED_9_9), self.SELECTED)
        self.labels = coin.SoSeparator()
        self.root.addChild(self.labels)
        view.getSceneGraph().addChild(self.root)

    def _markers(self, index):
        m = self.coin.SoMarkerSet()
        m.markerIndex = index
        return m

    def _layer(self, shape, color, line_width=None):
        sep = self.coin.SoSeparator()
        base = self.coin.SoBaseColor()
        base.rgb.setValue(*color)
        sep.addChild(base)
        if line_width:
            style = self.coin.SoDrawStyle()
            style.lineWidth = line_width
            sep.addChild(style)
        coords = self.coin.SoCoordinate3()
        sep.addChild(coords)
        sep.addChild(shape)
        self.root.addChild(sep)
        return coords

    @staticmethod
    def _set(coords, points):
        if points:
            coords.point.setValues(0, len(points), [(p.x, p.y, p.z) for p in points])
        coords.point.setNum(len(points))

    def show(self, points, curve, marked):
        self._set(self.curve, curve + curve[:1])
        self._set(self.points, points)
        self._set(self.marked, [points[i] for i in marked if i < len(points)])
        coin = self.coin
        self.labels.removeAllChildren()
        color = coin.SoBaseColor()
        color.rgb.setValue(*self.TEXT)
        font = coin.SoFont()
        font.size = 14
        self.labels.addChild(color)
        self.labels.addChild(font)
        for i, p in enumerate(points):
            sep, move, text = coin.SoSeparator(), coin.SoTranslation(), coin.SoText2()
            move.translation.setValue(p.x, p.y, p.z)
            text.string = f"  {i + 1}"
            sep.addChild(move)
            sep.addChild(text)
            self.labels.addChild(sep)

    def remove(self):
        try:
            scene = self.view.getSceneGraph()
            if scene.findChild(self.root) >= 0:
                scene.removeChild(self.root)
        except Exception:  # the view is gone with its document
            pass


class _PanelEvents(QtCore.QObject):
    """The boundary panel's mouse and keys, taken at the Qt level from the 3D view and the point list.

    FreeCAD 0.20's Coin event callbacks cannot carry a drag: the selection node consumes the button
    release over an object, so a callback never sees it, and navigation styles that turn the view with
    the left button take the motion. Here a press near a control point and the drag that follows belong
    to the panel; every other event passes on to FreeCAD, and a click (press and release in place) on the
    bone also adds a point. Delete, Backspace and Ctrl+Z are claimed before FreeCAD's shortcuts see them:
    its Delete would remove the selected document object, often the bone that was just clicked."""

    CLICK_PIXELS = 3  # press and release nearer than this (Qt pixels) make a click

    def __init__(self, panel):
        super().__init__()
        self.panel = panel
        self.pressed_at = None
        try:
            graphics = panel.view.graphicsView()
            self.viewport = graphics.viewport()
            view_widgets = [graphics, self.viewport]
        except Exception:  # no Qt view to watch: scripts still drive the panel by its methods
            self.viewport, view_widgets = None, []
        self.widgets = [panel.list] + view_widgets
        for w in self.widgets:
            w.installEventFilter(self)

    def unwatch(self):
        for w in self.widgets:
            try:
                w.removeEventFilter(self)
            except RuntimeError:  # the widget is gone already
                pass
        self.widgets = []

    def to_view(self, pos):
        """A Qt position in the viewport as the view's screen position (Coin's: origin at the bottom left,
        device pixels, which differ from Qt's by the device pixel ratio, 1.04 under Xvfb)."""
        w, h = self.panel.view.getSize()
        return (int(pos.x() * w / self.viewport.width()),
                int((self.viewport.height() - 1 - pos.y()) * h / self.viewport.height()))

    def eventFilter(self, widget, event):
        try:
            return self.handle(widget, event)
        except Exception as e:  # never break FreeCAD's event handling
            App.Console.PrintError(f"Surgical Template: boundary panel: {e}\n")
            return False

    def handle(self, widget, event):
        E, Qt, p = QtCore.QEvent, QtCore.Qt, self.panel
        kind = event.type()
        if p.done:
            return False
        if kind == E.ShortcutOverride and self.claims(event):
            event.accept()
            return True
        if kind == E.KeyPress:
            return self.key(widget, event)
        if widget is not self.viewport:
            return False
        left = kind in (E.MouseButtonPress, E.MouseButtonRelease) and event.button() == Qt.LeftButton
        if kind == E.MouseButtonPress and left:
            mods = event.modifiers() & (Qt.ControlModifier | Qt.ShiftModifier | Qt.AltModifier)
            if not mods and p.press(self.to_view(event.pos())):
                return True
            self.pressed_at = event.pos()
            return False
        if kind == E.MouseMove and p.dragging is not None:
            p.drag(self.to_view(event.pos()))
            return True
        if kind == E.MouseButtonRelease and left:
            if p.dragging is not None:
                p.release(self.to_view(event.pos()))
                return True
            start, self.pressed_at = self.pressed_at, None
            if start is not None and (event.pos() - start).manhattanLength() <= self.CLICK_PIXELS:
                if event.modifiers() & Qt.ControlModifier:
                    p.move_selected_to(self.to_view(event.pos()))
                else:
                    p.click(self.to_view(event.pos()))
            return False
        return kind == E.MouseButtonDblClick and p.dragging is not None

    def claims(self, event):
        Qt, key = QtCore.Qt, event.key()
        return (key in (Qt.Key_Delete, Qt.Key_Backspace)
                or (key == Qt.Key_Z and event.modifiers() & Qt.ControlModifier)
                or (key == Qt.Key_Escape and self.panel.dragging is not None))

    def key(self, widget, event):
        Qt, key, p = QtCore.Qt, event.key(), self.panel
        if key in (Qt.Key_Delete, Qt.Key_Backspace):
            p.remove_selected()
            return True
        if key == Qt.Key_Z and event.modifiers() & Qt.ControlModifier:
            p.undo()
            return True
        if key == Qt.Key_Escape and p.dragging is not None:
            p.cancel_drag()
            return True
        if key in (Qt.Key_Return, Qt.Key_Enter) and widget is not p.list:
            QtCore.QTimer.singleShot(0, lambda: None if p.done else p.accept())
            return True
        return False


class TubePanel:
    """Click the entry on the bone; the direction comes from the surface normal there, the view, or a
    second click (a point along the axis, e.g. where it leaves the bone: its distance is the depth).
    Sizes from a sleeve preset or typed in."""

    last = None  # the open panel, for scripts and tests
    DIRECTIONS = ("Surface normal at the entry", "View direction", "Second point (click it)")

    def __init__(self, bone, guide):
        import SurgicalTemplate
        TubePanel.last = self
        self.bone, self.guide = bone, guide
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Drilling tube")
        grid = QtGui.QFormLayout(self.form)
        self.presets = SurgicalTemplate.sleeve_presets()
        self.preset = QtGui.QComboBox()
        self.preset.addItem("(custom sizes)")
        for p in self.presets:
            self.preset.addItem(f"{p['name']}: {p['description']}")
        self.preset.currentIndexChanged.connect(self.apply_preset)
        grid.addRow("Sleeve preset", self.preset)
        self.fields = {}
        for key, label, value in (("inner", "Inner radius (mm)", preference("InnerRadius", 1.1)),
                                  ("outer", "Outer radius (mm)", preference("OuterRadius", 2.0)),
                                  ("length", "Length (mm)", preference("Length", 5.0)),
                                  ("offset", "Offset (mm)", preference("Offset", 3.0))):
            box = QtGui.QDoubleSpinBox()
            box.setRange(0.0, 100.0)
            box.setDecimals(2)
            box.setValue(value)
            grid.addRow(label, box)
            self.fields[key] = box
        self.mode = QtGui.QComboBox()
        self.mode.addItems(list(self.DIRECTIONS))
        self.mode.currentIndexChanged.connect(lambda _: self.reset())
        grid.addRow("Direction", self.mode)
        self.entry = QtGui.QLabel("click the entry point on the bone")
        grid.addRow("Entry", self.entry)
        self.axis = QtGui.QLabel("")
        grid.addRow("Axis", self.axis)
        self.picked = None  # (entry, direction into the bone, depth or 0)
        self.view = _view_of(bone.Document if bone is not None else App.ActiveDocument)
        self.callback = self.view.addEventCallback("SoMouseButtonEvent", self.on_mouse)

    def apply_preset(self, index):
        if index <= 0:
            return
        p = self.presets[index - 1]
        for key, field in (("inner", "inner_radius"), ("outer", "outer_radius"), ("length", "length"),
                           ("offset", "offset")):
            self.fields[key].setValue(p[field])

    def reset(self):
        self.picked = None
        self.entry.setText("click the entry point on the bone")
        self.axis.setText("")

    def on_mouse(self, info):
        if info.get("State") == "DOWN" and info.get("Button") == "BUTTON1":
            self.click(info["Position"])

    def _hit(self, position):
        hit = self.view.getObjectInfo(tuple(position))
        if not hit or self.bone is None or hit.get("Object") != self.bone.Name:
            return None, None
        p = App.Vector(hit["x"], hit["y"], hit["z"])
        # The clicked facet (FreeCAD names a mesh pick only "Main"): the first one a short ray along the
        # view meets through the picked point.
        d = App.Vector(self.view.getViewDirection())
        facets = self.bone.Mesh.nearestFacetOnRay(tuple(p - d * 0.05), tuple(d))
        normal = self.bone.Mesh.Facets[int(list(facets)[0])].Normal if facets else None
        return p, normal

    def click(self, position):
        """A click at a screen position: the entry, or in second-point mode the point along the axis."""
        p, normal = self._hit(position)
        if p is None:
            return False
        mode = self.mode.currentIndex()
        if mode == 2 and self.picked is not None and self.picked[2] == 0 and self.picked[1] is None:
            along = p - self.picked[0]
            if along.Length < 1e-6:
                return False
            self.picked = (self.picked[0], along.normalize(), (p - self.picked[0]).Length)
        else:
            if mode == 0:
                d = (normal if normal is not None else self.view.getViewDirection() * -1) * -1
            elif mode == 1:
                d = App.Vector(self.view.getViewDirection())
            else:
                d = None  # wait for the second point
            self.picked = (p, d, 0.0)
            self.entry.setText(f"{p.x:.2f}, {p.y:.2f}, {p.z:.2f}")
        e, d, depth = self.picked
        self.axis.setText("click a second point along the axis" if d is None else
                          f"direction {d.x:.3f}, {d.y:.3f}, {d.z:.3f}" + (f"; depth {depth:.1f} mm" if depth else ""))
        return True

    def accept(self):
        f = {k: v.value() for k, v in self.fields.items()}  # before closing deletes the widgets
        index = self.preset.currentIndex()
        preset = self.presets[index - 1]["name"] if index > 0 else ""
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        if self.picked is None or self.picked[1] is None:
            return True
        p, d, depth = self.picked
        code = (f"tube = SurgicalTemplate.make_tube(({p.x:.4f}, {p.y:.4f}, {p.z:.4f}), ({d.x:.5f}, {d.y:.5f}, "
                f"{d.z:.5f}), {f['inner']}, {f['outer']}, {f['length']}, {f['offset']}"
                + (f", depth={depth:.3f}" if depth else "") + (f", preset={preset!r}" if preset else "")
                + (f", guide={ref(self.guide)}" if self.guide is not None else "") + ")\n")
        run("Add drilling tube", code + "App.ActiveDocument.recompute()")
        return True

    def reject(self):
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        return True


class ValidatePanel:
    """The inspection of a guide or template in a task panel, its thickness map on the mesh."""

    last = None  # the open panel, for scripts and tests

    def __init__(self, obj):
        import SurgicalTemplate
        ValidatePanel.last = self
        self.obj = obj
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Validate")
        layout = QtGui.QVBoxLayout(self.form)
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            self.result = SurgicalTemplate.inspect(obj)
            self.error = None
        except (ValueError, RuntimeError) as e:
            self.result, self.error = None, str(e)
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        if self.error:
            App.Console.PrintError(f"Surgical Template: Validate failed: {self.error}\n")
            layout.addWidget(QtGui.QLabel(f"Could not inspect {obj.Label}:\n{self.error}"))
            return
        r = self.result
        verdict = QtGui.QLabel(("PASSED: " if r["passed"] else "FAILED: ") + obj.Label)
        verdict.setStyleSheet("font-weight: bold; color: %s" % ("#2a7d3a" if r["passed"] else "#b3261e"))
        layout.addWidget(verdict)
        solid = r["solid"]
        rows = [("Solid", solid["summary"]),
                ("Volume", f"{solid['volume']:.1f} mm\u00b3, {solid['components']} piece(s)"),
                ("Seating", "nothing in the bone" if r["vertices_in_bone"] == 0 else
                 f"{r['vertices_in_bone']} vertices in the bone, deepest {r['deepest_in_bone']:.3f} mm"),
                ("On the bone", f"{r['seated_vertices']} vertices within 0.01 mm of the clearance "
                                f"({r['clearance']:.2f} mm)")]
        form = QtGui.QFormLayout()
        for label, text in rows:
            value = QtGui.QLabel(text)
            value.setWordWrap(True)
            form.addRow(label, value)
        layout.addLayout(form)
        if r["bores"]:
            table = QtGui.QTableWidget(len(r["bores"]), 3)
            table.setHorizontalHeaderLabels(["Tube", "Bore margin (mm)", "Drill passes"])
            for i, b in enumerate(r["bores"]):
                for j, text in enumerate((b["name"], f"{b['margin']:.3f}", "yes" if b["open"] else "NO")):
                    table.setItem(i, j, QtGui.QTableWidgetItem(text))
            table.resizeColumnsToContents()
            layout.addWidget(table)
        layout.addWidget(QtGui.QLabel("Thickness map (distance from the bone):"))
        t, c = r["thickness"], r["clearance"]
        for distance, text in ((-1.0, "in the bone"), (c, f"{c:.2f} mm: seated"),
                               (c + t / 2, f"{c + t / 2:.2f} mm"), (c + t, f"{c + t:.2f} mm: outer surface"),
                               (c + 2 * t, "beyond: sleeves")):
            colour = QtGui.QColor.fromRgbF(*SurgicalTemplate.thickness_colour(distance, t, c))
            swatch = QtGui.QLabel(f"  \u25a0  {text}")
            swatch.setStyleSheet(f"color: {colour.name()}")
            layout.addWidget(swatch)
        self.show_map = QtGui.QCheckBox("Show the thickness map")
        self.show_map.setChecked(True)
        self.show_map.toggled.connect(lambda on: setattr(obj.ViewObject, "Coloring", bool(on)))
        layout.addWidget(self.show_map)
        (App.Console.PrintMessage if r["passed"] else App.Console.PrintError)(
            f"Surgical Template: {obj.Label}: {r['summary']}\n")

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        Gui.Control.closeDialog()
        return True

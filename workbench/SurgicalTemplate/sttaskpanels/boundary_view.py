"""What the boundary panel does in the 3D view: its overlay (the curve and the numbered control points,
drawn over the scene) and its mouse and keys, taken from the view and the point list."""
import FreeCAD as App
from pivy import coin
from PySide import QtCore


class Overlay:
    """What the boundary panel draws over the 3D view: the curve, and the control points as markers
    numbered in loop order, the selected (or dragged) ones highlighted. Coin nodes drawn on top of the
    scene and not pickable, so clicks reach the bone; never document objects, so they leave nothing in
    the undo history or a saved file, and removing the root node cleans up."""

    CURVE = (0.85, 0.10, 0.55)
    POINT = (1.00, 0.45, 0.00)
    SELECTED = (0.00, 0.75, 0.25)
    TEXT = (0.10, 0.10, 0.40)

    def __init__(self, view):
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


class PanelEvents(QtCore.QObject):
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

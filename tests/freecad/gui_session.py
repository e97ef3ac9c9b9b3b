"""Runs in a real FreeCAD window (under Xvfb in tests): the workbench's commands end to end, boundary
drawn by clicks at the screen positions of the control points, screenshots measured. Writes
$ST_OUT/gui-result.json; test_gui.py asserts on it."""
import json
import os
import sys
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_helpers import drop_parts, finish, tree_double_click  # noqa: E402

out, case_path = os.environ["ST_OUT"], os.environ["ST_CASE"]
result = {"errors": []}


def blue_fraction(path):
    """Fraction of the image's pixels in the guide's blue (shaded)."""
    image = QtGui.QImage(path)
    blue = total = 0
    for y in range(0, image.height(), 4):
        for x in range(0, image.width(), 4):
            c = QtGui.QColor(image.pixel(x, y))
            total += 1
            blue += c.blue() > c.red() + 40 and c.blue() > c.green() + 15
    return blue / max(total, 1)


def shot(name, view_direction=None):
    view = Gui.ActiveDocument.ActiveView
    if view_direction:
        view.setViewDirection(view_direction)
    view.fitAll()
    Gui.updateGui()
    path = os.path.join(out, name + ".png")
    view.saveImage(path, 800, 600, "White")
    result[name] = {"path": path, "blue": blue_fraction(path)}


def grab_window(path):
    """The main window with the 3D view painted in (a widget grab leaves the OpenGL view empty)."""
    mw = Gui.getMainWindow()
    pixmap = mw.grab()
    mdi = mw.findChild(QtGui.QMdiArea)
    sub = mdi.activeSubWindow() if mdi else None
    if sub is not None:
        widget = sub.widget()
        corner = widget.mapTo(mw, QtCore.QPoint(0, 0))
        view_png = os.path.join(out, "view-for-window.png")
        Gui.ActiveDocument.ActiveView.saveImage(view_png, widget.width(), widget.height(), "Current")
        painter = QtGui.QPainter(pixmap)
        painter.drawImage(corner, QtGui.QImage(view_png))
        painter.end()
    pixmap.save(path)


def work():
    try:
        Gui.activateWorkbench("SurgicalTemplateWorkbench")
        import st_commands
        import SurgicalTemplate

        result["workbench"] = Gui.activeWorkbench().name()
        result["commands"] = [c for c in Gui.listCommands() if c.startswith("SurgicalTemplate_")]
        # A default from the preferences page: the drawn template below must use it.
        App.ParamGet("User parameter:BaseApp/Preferences/Mod/SurgicalTemplate").SetFloat("Thickness", 2.8)
        # Open a case through the command's code path (the file dialog is the only part skipped).
        assert st_commands.open_case(case_path)
        doc = App.ActiveDocument
        guide = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Guide"][0]
        result["guide_state"] = list(guide.State)
        result["guide_status"] = guide.Status
        for o in doc.Objects:
            if o.TypeId == "Mesh::Feature" or getattr(o.Proxy if hasattr(o, "Proxy") else None, "kind", "") in (
                    "Template", "Tube", "Boundary"):
                o.ViewObject.Visibility = o.TypeId == "Mesh::Feature"
        case = json.load(open(case_path))
        shot("gui-guide", tuple(case["tubes"][0]["direction"]) if case.get("tubes") else None)
        # The whole window: workbench toolbar, tree, view (for the README).
        Gui.Selection.addSelection(guide)
        Gui.updateGui()
        window = os.path.join(out, "gui-window.png")
        grab_window(window)
        result["window"] = window
        Gui.Selection.clearSelection()

        # Draw a boundary by clicking on the bone in a second document, then design its template.
        bone_file = os.path.join(os.path.dirname(case_path), case["bone"])
        doc2 = App.newDocument("Drawn")
        bone = SurgicalTemplate.make_bone(bone_file, doc2)
        doc2.recompute()
        Gui.ActiveDocument.ActiveView.setViewDirection(tuple(case["tubes"][0]["direction"]))
        Gui.SendMsgToActiveView("ViewFit")
        Gui.updateGui()
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(bone)
        Gui.runCommand("SurgicalTemplate_DrawBoundary")
        panel = Gui.Control.activeDialog() and st_commands_active_panel()
        view = Gui.ActiveDocument.ActiveView
        clicks = 0
        for p in case["boundary"]["points"]:
            pos = view.getPointOnScreen(App.Vector(*p))
            clicks += bool(panel.click((int(pos[0]), int(pos[1]))))
            Gui.updateGui()
        result["clicks_on_bone"] = clicks
        result["preview_length"] = panel.preview.Shape.Length if panel.preview is not None else 0.0
        panel.accept()
        boundaries = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Boundary"]
        result["boundaries"] = [b.Name for b in boundaries]
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(boundaries[0])
        Gui.runCommand("SurgicalTemplate_CreateTemplate")
        templates = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Template"]
        result["drawn_template"] = {"facets": templates[0].Mesh.CountFacets, "state": list(templates[0].State),
                                    "status": templates[0].Status, "thickness": templates[0].Thickness.Value}
        # A tube by the Add tube command: click its entry on the bone; then the guide from the selection.
        Gui.runCommand("SurgicalTemplate_AddTube")
        tube_panel = st_commands.TubePanel.last
        templates[0].ViewObject.Visibility = False  # click the bone, not the template over it
        Gui.updateGui()
        pos = view.getPointOnScreen(App.Vector(*case["tubes"][0]["entry"]))
        result["tube_click"] = bool(tube_panel.click((int(pos[0]), int(pos[1]))))
        # "Continue": OK adds the tube and keeps the panel for the next one; Cancel then ends it.
        tube_panel.form.keep_going.setChecked(True)
        closes = tube_panel.accept()
        Gui.updateGui()
        tubes = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Tube"]
        result["continue"] = {"closes": closes, "open": bool(Gui.Control.activeDialog()), "tubes": len(tubes),
                              "entry_text": tube_panel.entry.text(),
                              "sizes": float(tube_panel.fields["outer"].property("rawValue"))}
        tube_panel.reject()
        Gui.updateGui()
        result["continue"]["closed_by_cancel"] = not Gui.Control.activeDialog()
        templates[0].ViewObject.Visibility = True
        tubes = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Tube"]
        result["continue"]["tubes_after_cancel"] = len(tubes)
        result["continue"]["outer"] = tubes[0].OuterDiameter.Value if tubes else None
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(templates[0])
        for t in tubes:
            Gui.Selection.addSelection(t)
        Gui.runCommand("SurgicalTemplate_CreateGuide")
        guides = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Guide"]
        result["drawn_guide"] = {"tubes": len(tubes), "guides": len(guides),
                                 "state": list(guides[0].State) if guides else [],
                                 "status": guides[0].Status if guides else ""}
        boundaries[0].ViewObject.LineColor = (0.85, 0.26, 0.23)
        Gui.Selection.clearSelection()
        result["template_hidden_by_guide"] = not templates[0].ViewObject.Visibility
        shot("gui-drawn-template")
        result["edit"] = edit_drawn_boundary(doc2, boundaries[0], bone)
        result["cutting"] = cutting_commands()
    except Exception:
        result["errors"].append(traceback.format_exc())
    finally:
        finish(os.path.join(out, "gui-result.json"), result)


def to_qt(view, position):
    """A screen position of the view (Coin's: origin at the bottom left, device pixels) in the viewport's
    Qt coordinates, and back (they differ by the device pixel ratio: 1.04 under Xvfb)."""
    viewport = view.graphicsView().viewport()
    w, h = view.getSize()
    return QtCore.QPoint(round(position[0] * viewport.width() / w),
                         round(viewport.height() - 1 - position[1] * viewport.height() / h))


def from_qt(view, point):
    viewport = view.graphicsView().viewport()
    w, h = view.getSize()
    return (int(point.x() * w / viewport.width()), int((viewport.height() - 1 - point.y()) * h / viewport.height()))


def mouse(view, kind, point, buttons=QtCore.Qt.LeftButton, modifiers=QtCore.Qt.NoModifier):
    """A real Qt mouse event on the 3D view's viewport: FreeCAD and the panel see what a user's mouse makes."""
    button = QtCore.Qt.NoButton if kind == QtCore.QEvent.MouseMove else QtCore.Qt.LeftButton
    QtGui.QApplication.sendEvent(view.graphicsView().viewport(),
                                 QtGui.QMouseEvent(kind, point, button, buttons, modifiers))
    Gui.updateGui()


def key(widget, code):
    """A key press as Qt delivers it: first the shortcut override (FreeCAD's shortcuts, e.g. Delete = delete
    the selected object, fire unless the focus widget accepts it), then the key. True if it was overridden."""
    override = QtGui.QKeyEvent(QtCore.QEvent.ShortcutOverride, code, QtCore.Qt.NoModifier)
    override.ignore()
    QtGui.QApplication.sendEvent(widget, override)
    if override.isAccepted():
        QtGui.QApplication.sendEvent(widget, QtGui.QKeyEvent(QtCore.QEvent.KeyPress, code, QtCore.Qt.NoModifier))
    Gui.updateGui()
    return override.isAccepted()


def cutting_commands():
    """The tibia cutting guide opened by the command; its label removed, then added back by Add label at a
    point picked on the guide, and a slot added by Add saw slot from the view: each one undo step, the
    guide valid after each (a refusal shows the kernel's message and leaves the guide as it was)."""
    import st_commands
    r = {"warnings": []}
    warning = QtGui.QMessageBox.warning
    QtGui.QMessageBox.warning = lambda parent, title, text, *rest: r["warnings"].append(text)
    try:
        assert st_commands.open_case(os.path.join(os.path.dirname(case_path), "tibia-osteotomy.json"))
        doc = App.ActiveDocument
        doc.UndoMode = 1
        guide = [o for o in doc.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Guide"][0]
        drop_parts(guide, "Label")
        guide.Label = "TIB 1"  # the case's name, the label's default text (the example's is too long for it)
        doc.recompute()
        view = Gui.getDocument(doc.Name).ActiveView
        view.setCameraOrientation(App.Rotation(App.Vector(1, 0, 0), 90))  # looking along +y, +z up on screen
        Gui.updateGui()
        Gui.Selection.clearSelection()
        # A click on the guide selects one of its facets at the point clicked.
        Gui.Selection.addSelection(doc.Name, guide.Name, "Facet1", 621.0, 412.0, 350.0)
        Gui.runCommand("SurgicalTemplate_AddLabel")
        Gui.updateGui()
        labels = guide.Proxy.labels_of(guide)
        r["label"] = {"texts": [l["text"] for l in labels], "state": list(guide.State), "case": guide.Label,
                      "up": labels[0]["up"] if labels else None}
        slots_before = len(guide.Proxy.slots_of(guide))
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(doc.Name, guide.Name, "Facet1", 627.0, 413.0, 366.0)
        Gui.runCommand("SurgicalTemplate_AddSlot")
        Gui.updateGui()
        r["slot"] = {"before": slots_before, "after": len(guide.Proxy.slots_of(guide)), "state": list(guide.State)}
        doc.undo()
        doc.recompute()
        r["after_undo"] = {"slots": len(guide.Proxy.slots_of(guide)), "labels": len(guide.Proxy.labels_of(guide))}
    finally:
        QtGui.QMessageBox.warning = warning
    return r


def task_button(which):
    """The task panel's OK or Cancel button."""
    for box in Gui.getMainWindow().findChildren(QtGui.QDialogButtonBox):
        button = box.button(which)
        if button is not None and button.isVisible():
            return button
    return None


def colour_pixels(path, rgb, tolerance=40):
    """Pixels of the image within `tolerance` of a colour (the panel's markers)."""
    image = QtGui.QImage(path)
    target = [int(255 * c) for c in rgb]
    count = 0
    for y in range(image.height()):
        for x in range(image.width()):
            c = QtGui.QColor(image.pixel(x, y))
            count += max(abs(c.red() - target[0]), abs(c.green() - target[1]), abs(c.blue() - target[2])) <= tolerance
    return count


def bone_on_ray(view, bone, position):
    """Where the view ray at a screen position meets the bone, by the mesh itself (not by picking)."""
    d = App.Vector(view.getViewDirection())
    origin = App.Vector(view.getPoint(*position)) - d * 1000.0
    hits = bone.Mesh.nearestFacetOnRay(tuple(origin), tuple(d))
    return App.Vector(*list(hits.values())[0]) if hits else None


def edit_drawn_boundary(doc, boundary, bone):
    """The boundary edited in its panel as a user does it: opened by a double-click in the tree, one
    point dragged to a new place, one added by a click near a segment, one removed with the Delete key,
    OK; then Undo. Another edit is cancelled. All mouse and key input goes through Qt events."""
    import st_commands
    from sttaskpanels.boundary_view import Overlay
    r = {}
    for o in doc.Objects:  # the guide over the bone would hide the view of the points
        if getattr(getattr(o, "Proxy", None), "kind", "") == "Guide":
            o.ViewObject.Visibility = False
    gui_doc = Gui.getDocument(doc.Name)
    view = gui_doc.ActiveView
    view.setViewDirection(tuple(App.Vector(view.getViewDirection())))
    view.fitAll()
    Gui.updateGui()
    before = [App.Vector(p) for p in boundary.Points]
    undo_count = doc.UndoCount
    r["before"] = [tuple(p) for p in before]

    st_commands.BoundaryPanel.last = None
    double_clicked = tree_double_click(doc, boundary)
    panel = st_commands.BoundaryPanel.last
    r["opened_by_double_click"] = double_clicked and panel is not None and panel.boundary == boundary
    if not r["opened_by_double_click"]:  # so that the rest still runs and reports
        gui_doc.setEdit(boundary.Name, 0)
        panel = st_commands.BoundaryPanel.last
    r["in_edit"] = gui_doc.getInEdit() is not None and gui_doc.getInEdit().Object.Name == boundary.Name
    r["panel_points"] = len(panel.points)
    r["nearest_checked"] = panel.nearest.isChecked()
    scene = view.getSceneGraph()
    r["overlay_shown"] = scene.findChild(panel.overlay.root) >= 0

    # Drag: press on a visible control point, move towards the middle of the region, release on the bone.
    screen = [view.getPointOnScreen(p) for p in before]
    centre = (sum(s[0] for s in screen) / len(screen), sum(s[1] for s in screen) / len(screen))
    drag = None
    for k in range(len(before)):
        s = screen[k]
        target_qt = to_qt(view, (s[0] + 0.3 * (centre[0] - s[0]), s[1] + 0.3 * (centre[1] - s[1])))
        target = from_qt(view, target_qt)
        if panel.point_at(from_qt(view, to_qt(view, s))) == k and bone_on_ray(view, bone, target) is not None:
            drag = k, to_qt(view, s), target_qt, target
            break
    k, start_qt, target_qt, target = drag
    mouse(view, QtCore.QEvent.MouseMove, start_qt, QtCore.Qt.NoButton)
    mouse(view, QtCore.QEvent.MouseButtonPress, start_qt)
    r["dragging_started"] = panel.dragging is not None and panel.dragging["index"] == k
    for t in (0.25, 0.5, 0.75, 1.0):
        mouse(view, QtCore.QEvent.MouseMove, start_qt + (target_qt - start_qt) * t)
    mouse(view, QtCore.QEvent.MouseButtonRelease, target_qt, QtCore.Qt.NoButton)
    expected = bone_on_ray(view, bone, target)
    moved = App.Vector(panel.points[k])
    r["drag"] = {"index": k, "count": len(panel.points), "moved_by": (moved - before[k]).Length,
                 "off_target": (moved - expected).Length, "others_kept": all(
                     (panel.points[i] - before[i]).Length < 1e-9 for i in range(len(before)) if i != k)}

    # Insert: a click near the middle of the longest visible segment away from the moved point.
    pts = [App.Vector(p) for p in panel.points]
    n = len(pts)

    def chord_distance(i, q):
        a, b = pts[i], pts[(i + 1) % n]
        t = max(0.0, min(1.0, (q - a).dot(b - a) / (b - a).dot(b - a)))
        return (a + (b - a) * t - q).Length

    insert = None
    for i in sorted(range(n), key=lambda i: -(pts[(i + 1) % n] - pts[i]).Length):
        if k in (i, (i + 1) % n):
            continue
        mid = view.getPointOnScreen((pts[i] + pts[(i + 1) % n]) * 0.5)
        click_qt = to_qt(view, mid)
        at = from_qt(view, click_qt)
        q = bone_on_ray(view, bone, at)
        far_from_points = all(((x - at[0]) ** 2 + (y - at[1]) ** 2) ** 0.5 > 2 * panel.PICK_PIXELS
                              for x, y in (view.getPointOnScreen(p) for p in pts))
        if q is not None and far_from_points and min(range(n), key=lambda j: chord_distance(j, q)) == i:
            insert = i, click_qt, q
            break
    i, click_qt, q = insert
    mouse(view, QtCore.QEvent.MouseMove, click_qt, QtCore.Qt.NoButton)
    mouse(view, QtCore.QEvent.MouseButtonPress, click_qt)
    mouse(view, QtCore.QEvent.MouseButtonRelease, click_qt, QtCore.Qt.NoButton)
    after_insert = [App.Vector(p) for p in panel.points]
    new = [j for j in range(len(after_insert)) if all((after_insert[j] - p).Length > 1e-6 for p in pts)]
    r["insert"] = {"segment": i, "count": len(after_insert), "new": new,
                   "off_click": (after_insert[new[0]] - q).Length if new else None,
                   "previous_is_segment_start": bool(new) and (after_insert[new[0] - 1] - pts[i]).Length < 1e-9,
                   "next_is_segment_end": bool(new) and
                   (after_insert[(new[0] + 1) % len(after_insert)] - pts[(i + 1) % n]).Length < 1e-9}

    # Delete: select a row in the list, press Delete there (the bone selected by the clicks must survive).
    gone = next(j for j in range(len(after_insert)) if j != k and j not in new)
    panel.select(gone)
    panel.list.setFocus()
    Gui.updateGui()
    r["delete_key_claimed"] = key(panel.list, QtCore.Qt.Key_Delete)
    r["delete"] = {"index": gone, "count": len(panel.points), "removed": all(
        (p - after_insert[gone]).Length > 1e-9 for p in panel.points)}
    r["bone_still_there"] = doc.getObject(bone.Name) is not None
    expected_points = [p for j, p in enumerate(after_insert) if j != gone]

    # The markers, one selected, in a screenshot.
    panel.select(0)
    shot("gui-edit-boundary")
    r["marker_pixels"] = colour_pixels(result["gui-edit-boundary"]["path"], Overlay.POINT)
    r["selected_pixels"] = colour_pixels(result["gui-edit-boundary"]["path"], Overlay.SELECTED)
    r["curve_pixels"] = colour_pixels(result["gui-edit-boundary"]["path"], Overlay.CURVE)
    panel.select()

    ok = task_button(QtGui.QDialogButtonBox.Ok)
    r["ok_button"] = ok is not None
    ok.click() if ok is not None else panel.accept()
    Gui.updateGui()
    after = [App.Vector(p) for p in boundary.Points]
    r["after"] = {"count": len(after), "as_edited": len(after) == len(expected_points) and all(
        (a - e).Length < 1e-3 for a, e in zip(after, expected_points)),
        "length": boundary.Shape.Length, "valid": boundary.Shape.isValid(), "state": list(boundary.State),
        "undo_steps": doc.UndoCount - undo_count, "undo_name": doc.UndoNames[0] if doc.UndoNames else "",
        "dialog_open": bool(Gui.Control.activeDialog()), "in_edit": gui_doc.getInEdit() is not None,
        "overlay_left": scene.findChild(panel.overlay.root) >= 0,
        "preview_objects": [o.Name for o in doc.Objects if o.Name.startswith("BoundaryPreview")]}
    doc.undo()
    doc.recompute()
    r["undone"] = {"as_before": len(boundary.Points) == len(before) and all(
        (a - b).Length < 1e-6 for a, b in zip(boundary.Points, before)),
        "length": boundary.Shape.Length, "valid": boundary.Shape.isValid(), "state": list(boundary.State)}

    # Cancel leaves the boundary as it is.
    undo_count = doc.UndoCount
    gui_doc.setEdit(boundary.Name, 0)
    cancelled = st_commands.BoundaryPanel.last
    cancelled.delete(0)
    cancel = task_button(QtGui.QDialogButtonBox.Cancel)
    cancel.click() if cancel is not None else cancelled.reject()
    Gui.updateGui()
    r["cancelled"] = {"unchanged": len(boundary.Points) == len(before), "undo_steps": doc.UndoCount - undo_count,
                      "dialog_open": bool(Gui.Control.activeDialog()), "in_edit": gui_doc.getInEdit() is not None,
                      "overlay_left": scene.findChild(cancelled.overlay.root) >= 0}
    return r


def st_commands_active_panel():
    """The task panel the DrawBoundary command opened."""
    import st_commands
    return st_commands.BoundaryPanel.last


QtCore.QTimer.singleShot(1000, work)

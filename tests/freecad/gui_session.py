"""Runs in a real FreeCAD window (under Xvfb in tests): the workbench's commands end to end, boundary
drawn by clicks at the screen positions of the control points, screenshots measured. Writes
$ST_OUT/gui-result.json; test_gui.py asserts on it."""
import json
import os
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

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
        tube_panel.accept()
        templates[0].ViewObject.Visibility = True
        tubes = [o for o in doc2.Objects if getattr(getattr(o, "Proxy", None), "kind", "") == "Tube"]
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
    except Exception:
        result["errors"].append(traceback.format_exc())
    finally:
        with open(os.path.join(out, "gui-result.json"), "w") as f:
            json.dump(result, f, indent=1)
        for name in list(App.listDocuments()):
            App.closeDocument(name)
        QtCore.QTimer.singleShot(0, Gui.getMainWindow().close)


def st_commands_active_panel():
    """The task panel the DrawBoundary command opened."""
    import st_commands
    return st_commands.BoundaryPanel.last


QtCore.QTimer.singleShot(1000, work)

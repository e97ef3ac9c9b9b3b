"""Runs in a real FreeCAD window (under Xvfb, see test_native.py): a document made without the GUI opens
with the workbench's view providers (icons, the tree nested, shell and tubes hidden under the guide);
deleting the guide shows them again and undo brings the guide back; the workbench's file types are
registered. Writes $ST_OUT/native-result.json."""
import os
import sys
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_helpers import finish, tree_context_menu, tree_double_click  # noqa: E402

out, document = os.environ["ST_OUT"], os.environ["ST_DOC"]
result = {"errors": []}


def kind(o):
    return getattr(getattr(o, "Proxy", None), "kind", "")


def answer_dialogs():
    """Accepts a modal question as a user would (Std_Delete may ask), noting its text."""
    w = QtGui.QApplication.activeModalWidget()
    if w is not None:
        result.setdefault("dialogs", []).append(getattr(w, "text", lambda: w.windowTitle())())
        buttons = w.findChildren(QtGui.QPushButton)
        yes = [b for b in buttons if b.text().replace("&", "") in ("Yes", "OK")]
        (yes[0].click() if yes else w.accept())


def edit_a_tube(doc):
    """Double-click a tube in the tree: its panel opens with its numbers; a changed outer diameter shows on
    the guide at once; Cancel puts it back; OK keeps a change as one undo step."""
    from sttaskpanels.tube import TubePanel
    guide = [o for o in doc.Objects if kind(o) == "Guide"][0]
    tube = guide.Tubes[0]
    r = result["edit"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume}
    TubePanel.last = None
    r["dialog_before"] = bool(Gui.Control.activeDialog())
    for _ in range(5):  # let the tree settle after the document opened
        QtGui.QApplication.processEvents()
        QtCore.QThread.msleep(100)
    r["double_clicked"] = tree_double_click(doc, tube)
    r["in_edit_after_click"] = str(Gui.getDocument(doc.Name).getInEdit())
    panel = TubePanel.last
    r["opened"] = panel is not None and panel.tube == tube
    if panel is None:  # so that the rest still runs and reports
        Gui.getDocument(doc.Name).setEdit(tube.Name, 0)
        panel = TubePanel.last
    gui_doc = Gui.getDocument(doc.Name)
    r["in_edit"] = gui_doc.getInEdit() is not None and gui_doc.getInEdit().Object.Name == tube.Name
    r["panel_outer"] = float(panel.fields["outer"].property("rawValue"))
    r["panel_unit"] = panel.fields["outer"].property("unit")
    panel.fields["outer"].setProperty("rawValue", r["outer"] + 0.5)
    Gui.updateGui()
    r["preview"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume}
    panel.reject()
    Gui.updateGui()
    r["cancelled"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume,
                      "in_edit": gui_doc.getInEdit() is not None}
    undo = doc.UndoCount
    gui_doc.setEdit(tube.Name, 0)
    TubePanel.last.fields["outer"].setProperty("rawValue", r["outer"] + 0.3)
    TubePanel.last.accept()
    Gui.updateGui()
    r["accepted"] = {"outer": tube.OuterDiameter.Value, "undo_steps": doc.UndoCount - undo}
    doc.undo()
    r["undone"] = {"outer": tube.OuterDiameter.Value}


def type_an_expression(doc):
    """In the tube's panel, the outer diameter typed as an expression as a user does: "=" in the field
    opens FreeCAD's expression editor, "Spreadsheet.D" in it, OK; then the panel's OK. The spreadsheet
    then drives the guide."""
    from sttaskpanels.tube import TubePanel
    guide = [o for o in doc.Objects if kind(o) == "Guide"][0]
    tube = guide.Tubes[0]
    sheet = doc.addObject("Spreadsheet::Sheet", "Spreadsheet")
    sheet.set("A1", "4.8 mm")
    sheet.setAlias("A1", "D")
    doc.recompute()
    r = result["expression"] = {"before": {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume}}
    Gui.getDocument(doc.Name).setEdit(tube.Name, 0)
    field = TubePanel.last.fields["outer"]
    field.setFocus()
    QtGui.QApplication.sendEvent(field, QtGui.QKeyEvent(QtCore.QEvent.KeyPress, QtCore.Qt.Key_Equal,
                                                        QtCore.Qt.NoModifier, "="))
    Gui.updateGui()
    editors = [w for w in QtGui.QApplication.allWidgets()
               if w.metaObject().className().endswith("DlgExpressionInput") and w.isVisible()]
    r["editor_opened"] = len(editors)
    if editors:
        line = [e for e in editors[0].findChildren(QtGui.QLineEdit) if e.objectName() == "expression"][0]
        line.setText("Spreadsheet.D")
        Gui.updateGui()
        editors[0].accept()
        Gui.updateGui()
    r["field"] = {"value": float(field.property("rawValue")), "expression": field.property("expression")}
    TubePanel.last.accept()
    Gui.updateGui()
    doc.recompute()
    r["after"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume,
                  "expressions": {p.lstrip("."): e for p, e in tube.ExpressionEngine}, "state": list(guide.State)}
    sheet.set("A1", "5.2 mm")
    doc.recompute()
    r["sheet_changed"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume}


def wait(ms):
    """Lets Qt run for a while (timers, repaints), as the user's pause does."""
    end = QtCore.QTime.currentTime().addMSecs(ms)
    while QtCore.QTime.currentTime() < end:
        QtGui.QApplication.processEvents()
        QtCore.QThread.msleep(20)


def edit_template_and_guide(doc):
    """Double-click the template in the tree: its panel with its numbers; a thicker template previewed on
    the guide; Cancel puts it back; OK with a thickness and an insertion is one undo step. Double-click
    the guide: its tolerance and parts."""
    from sttaskpanels.parameters import ParameterPanel
    guide = [o for o in doc.Objects if kind(o) == "Guide"][0]
    template = guide.Shell
    r = result["template_panel"] = {"thickness": template.Thickness.Value, "volume": guide.Mesh.Volume,
                                    "insertion": template.Insertion}
    ParameterPanel.last = None
    App.setActiveDocument(doc.Name)   # (an example was opened and closed just before)
    Gui.ActiveDocument = Gui.getDocument(doc.Name)
    wait(300)
    r["double_clicked"] = tree_double_click(doc, template)
    panel = ParameterPanel.last
    r["opened"] = panel is not None and panel.obj == template
    if panel is None:
        Gui.getDocument(doc.Name).setEdit(template.Name, 0)
        panel = ParameterPanel.last
    r["panel"] = {"thickness": float(panel.fields["thickness"].property("rawValue")),
                  "unit": panel.fields["thickness"].property("unit"), "insertion": panel.form.insertion.currentText()}
    panel.fields["thickness"].setProperty("rawValue", r["thickness"] + 0.5)
    wait(1500)
    doc.recompute()
    r["preview"] = {"thickness": template.Thickness.Value, "volume": guide.Mesh.Volume}
    panel.reject()
    Gui.updateGui()
    r["cancelled"] = {"thickness": template.Thickness.Value, "volume": guide.Mesh.Volume,
                      "dialog": bool(Gui.Control.activeDialog())}
    undo = doc.UndoCount
    Gui.getDocument(doc.Name).setEdit(template.Name, 0)
    panel = ParameterPanel.last
    panel.fields["thickness"].setProperty("rawValue", r["thickness"] + 0.3)
    panel.form.insertion.setCurrentIndex(2)   # None
    panel.accept()
    Gui.updateGui()
    r["accepted"] = {"thickness": template.Thickness.Value, "insertion": template.Insertion,
                     "undo_steps": doc.UndoCount - undo, "state": list(guide.State), "volume": guide.Mesh.Volume}
    doc.undo()
    doc.recompute()
    r["undone"] = {"thickness": template.Thickness.Value, "insertion": template.Insertion}
    ParameterPanel.last = None
    tree_double_click(doc, guide)
    panel = ParameterPanel.last
    r["guide_panel"] = None if panel is None else {
        "tolerance": float(panel.fields["tolerance"].property("rawValue")), "parts": panel.form.parts.text()}
    if panel is not None:
        panel.reject()
    Gui.updateGui()


def drag_and_drop(doc):
    """A tube dragged out of the guide in the tree leaves it (and shows); dropped back on the guide it
    joins it again: the guide as before. Through the view providers' drag-and-drop calls the tree makes."""
    guide = [o for o in doc.Objects if kind(o) == "Guide"][0]
    bone = guide.Shell.Boundary.Bone
    tube = guide.Tubes[-1]
    doc.recompute()
    r = result["drag_drop"] = {"tubes": len(guide.Tubes), "volume": guide.Mesh.Volume}
    vo = guide.ViewObject
    r["can_drag"] = bool(vo.canDragObject(tube))
    vo.dragObject(tube)
    Gui.updateGui()
    r["dragged"] = {"tubes": len(guide.Tubes), "volume": guide.Mesh.Volume, "visible": tube.ViewObject.Visibility}
    r["can_drop"] = {"tube": bool(vo.canDropObject(tube)), "bone": bool(vo.canDropObject(bone)),
                     "template": bool(vo.canDropObject(guide.Shell))}
    vo.dropObject(tube, None, "", [])
    Gui.updateGui()
    r["dropped"] = {"tubes": len(guide.Tubes), "volume": guide.Mesh.Volume, "visible": tube.ViewObject.Visibility,
                    "state": list(guide.State)}


def open_an_example():
    """Surgical Template > Open example > tibia-osteotomy: a new document with the example's guide."""
    Gui.activateWorkbench("SurgicalTemplateWorkbench")
    menu = [m for m in Gui.getMainWindow().menuBar().findChildren(QtGui.QMenu)
            if m.title().replace("&", "") == "Surgical Template"][0]
    group = [a for a in menu.actions() if a.text().replace("&", "") == "Open example"][0]
    entries = group.menu().actions()
    before = set(App.listDocuments())
    [a for a in entries if a.text() == "tibia-osteotomy"][0].trigger()
    Gui.updateGui()
    new = [App.getDocument(n) for n in set(App.listDocuments()) - before]
    guides = [o for d in new for o in d.Objects if kind(o) == "Guide"]
    result["example"] = {"documents": len(new), "guides": [g.Label for g in guides],
                         "state": list(guides[0].State) if guides else [], "facets": guides[0].Mesh.CountFacets if guides else 0}
    for d in new:
        App.closeDocument(d.Name)
    Gui.updateGui()


def preferences_page():
    """Edit > Preferences as a user opens it: the workbench's group with its icon, its page's length
    fields unit-aware (mm), showing the stored defaults."""
    seen = result["preferences"] = {}
    App.ParamGet("User parameter:BaseApp/Preferences/Mod/SurgicalTemplate").SetFloat("OuterDiameter", 4.6)

    def look():
        dialog = QtGui.QApplication.activeModalWidget()
        try:
            items = dialog.findChildren(QtGui.QListWidget)[0]
            for i in range(items.count()):
                item = items.item(i)
                if item.text() == "Surgical Template":
                    seen["icon"] = not item.icon().isNull()
                    items.setCurrentItem(item)
            Gui.updateGui()
            def text(value):
                return bytes(value).decode() if isinstance(value, (bytes, QtCore.QByteArray)) else str(value)

            boxes = [w for w in dialog.findChildren(QtGui.QAbstractSpinBox)
                     if w.metaObject().className() == "Gui::PrefUnitSpinBox"
                     and text(w.property("prefPath")) == "Mod/SurgicalTemplate"]
            seen["spin_boxes"] = sorted({w.metaObject().className() for w in dialog.findChildren(QtGui.QAbstractSpinBox)})
            seen["fields"] = {text(w.property("prefEntry")): [float(w.property("rawValue")), w.property("unit")]
                              for w in boxes}
        except Exception:
            result["errors"].append(traceback.format_exc())
        finally:
            dialog.reject()

    QtCore.QTimer.singleShot(800, look)
    Gui.runCommand("Std_DlgPreferences")


def menus_and_toolbars(doc, guide):
    """The workbench's menu (groups between separators, shortcuts), its toolbars, and the tree's context
    menu on a guide."""
    Gui.activateWorkbench("SurgicalTemplateWorkbench")
    Gui.updateGui()
    mw = Gui.getMainWindow()
    menu = [m for m in mw.menuBar().findChildren(QtGui.QMenu) if m.title().replace("&", "") == "Surgical Template"][0]
    result["menu"] = [["", ""] if a.isSeparator() else [a.text().replace("&", ""), a.shortcut().toString()]
                      for a in menu.actions()]
    examples = [a for a in menu.actions() if a.text().replace("&", "") == "Open example"]
    result["examples_menu"] = [a.text() for a in examples[0].menu().actions()] if examples and examples[0].menu() else []
    result["toolbars"] = {t.windowTitle(): len([a for a in t.actions() if not a.isSeparator()])
                          for t in mw.findChildren(QtGui.QToolBar) if t.windowTitle().startswith("Surgical")}
    Gui.Selection.clearSelection()
    Gui.Selection.addSelection(guide)
    result["context_menu"] = tree_context_menu(doc, guide)


def work():
    try:
        doc = App.openDocument(document)
        Gui.updateGui()
        ours = [o for o in doc.Objects if kind(o)]
        result["view_providers"] = {o.Label: type(o.ViewObject.Proxy).__name__ for o in ours}
        result["icons"] = {o.Label: os.path.basename(o.ViewObject.Proxy.getIcon()) for o in ours
                           if hasattr(o.ViewObject.Proxy, "getIcon")}
        guide = [o for o in ours if kind(o) == "Guide"][0]
        result["children"] = sorted(c.Label for c in guide.ViewObject.Proxy.claimChildren())
        result["visible"] = {o.Label: bool(o.ViewObject.Visibility) for o in ours}
        doc.UndoMode = 1
        edit_a_tube(doc)
        type_an_expression(doc)
        preferences_page()
        open_an_example()
        drag_and_drop(doc)
        edit_template_and_guide(doc)
        menus_and_toolbars(doc, guide)
        # Delete the guide as a user does (selection, Std_Delete): its shell and tubes show again.
        doc.UndoMode = 1
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(guide)
        timer = QtCore.QTimer()
        timer.timeout.connect(answer_dialogs)
        timer.start(200)
        Gui.runCommand("Std_Delete", 0)
        timer.stop()
        Gui.updateGui()
        result["after_delete"] = {"guides": len([o for o in doc.Objects if kind(o) == "Guide"]),
                                  "visible": {o.Label: bool(o.ViewObject.Visibility) for o in doc.Objects
                                              if kind(o) in ("Template", "Tube")}}
        doc.undo()
        Gui.updateGui()
        result["after_undo"] = {"guides": len([o for o in doc.Objects if kind(o) == "Guide"])}
        result["import_types"] = App.getImportType("json")
    except Exception:
        result["errors"].append(traceback.format_exc())
    finally:
        finish(os.path.join(out, "native-result.json"), result)


QtCore.QTimer.singleShot(500, work)

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
    r["panel_outer"] = panel.fields["outer"].value()
    panel.fields["outer"].setValue(r["outer"] + 0.5)
    Gui.updateGui()
    r["preview"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume}
    panel.reject()
    Gui.updateGui()
    r["cancelled"] = {"outer": tube.OuterDiameter.Value, "volume": guide.Mesh.Volume,
                      "in_edit": gui_doc.getInEdit() is not None}
    undo = doc.UndoCount
    gui_doc.setEdit(tube.Name, 0)
    TubePanel.last.fields["outer"].setValue(r["outer"] + 0.3)
    TubePanel.last.accept()
    Gui.updateGui()
    r["accepted"] = {"outer": tube.OuterDiameter.Value, "undo_steps": doc.UndoCount - undo}
    doc.undo()
    r["undone"] = {"outer": tube.OuterDiameter.Value}


def menus_and_toolbars(doc, guide):
    """The workbench's menu (groups between separators, shortcuts), its toolbars, and the tree's context
    menu on a guide."""
    Gui.activateWorkbench("SurgicalTemplateWorkbench")
    Gui.updateGui()
    mw = Gui.getMainWindow()
    menu = [m for m in mw.menuBar().findChildren(QtGui.QMenu) if m.title().replace("&", "") == "Surgical Template"][0]
    result["menu"] = [["", ""] if a.isSeparator() else [a.text().replace("&", ""), a.shortcut().toString()]
                      for a in menu.actions()]
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

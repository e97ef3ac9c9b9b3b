"""Runs in a real FreeCAD window (under Xvfb, see test_native.py): a document made without the GUI opens
with the workbench's view providers (icons, the tree nested, shell and tubes hidden under the guide);
deleting the guide shows them again and undo brings the guide back; the workbench's file types are
registered. Writes $ST_OUT/native-result.json."""
import json
import os
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

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
        App.closeDocument(doc.Name)  # changed: closing the window would ask to save it
    except Exception:
        result["errors"].append(traceback.format_exc())
    finally:
        with open(os.path.join(out, "native-result.json"), "w") as f:
            json.dump(result, f, indent=1)
        Gui.getMainWindow().close()


QtCore.QTimer.singleShot(500, work)

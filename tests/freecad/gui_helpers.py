"""What the GUI sessions share: acting on FreeCAD's window as a user does, and ending a session."""
import json

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui


def finish(path, result):
    """Writes the session's result, closes its documents unsaved (closing the window would ask to save
    changed ones) and then the window."""
    with open(path, "w") as f:
        json.dump(result, f, indent=1)
    for name in list(App.listDocuments()):
        App.closeDocument(name)
    QtCore.QTimer.singleShot(0, Gui.getMainWindow().close)


def drop_parts(guide, kind):
    """Removes the guide's Slot or Label objects from it and from the document."""
    for p in [p for p in guide.Parts if p.Proxy.kind == kind]:
        guide.Parts = [q for q in guide.Parts if q != p]
        guide.Document.removeObject(p.Name)


def tree_double_click(doc, obj):
    """Double-clicks the object's item under its document in the tree view, as a user does."""
    found = tree_item(doc, obj)
    if found is None:
        return False
    tree, item = found
    at = tree.visualItemRect(item).center()
    for kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease,
                 QtCore.QEvent.MouseButtonDblClick, QtCore.QEvent.MouseButtonRelease):
        buttons = QtCore.Qt.NoButton if kind == QtCore.QEvent.MouseButtonRelease else QtCore.Qt.LeftButton
        QtGui.QApplication.sendEvent(tree.viewport(), QtGui.QMouseEvent(
            kind, at, QtCore.Qt.LeftButton, buttons, QtCore.Qt.NoModifier))
    Gui.updateGui()
    return True


def tree_item(doc, obj):
    """(tree, item) of the object under its document in the tree view, shown and scrolled to; else None."""
    for tree in Gui.getMainWindow().findChildren(QtGui.QTreeWidget):
        top = [tree.topLevelItem(i) for i in range(tree.topLevelItemCount())]  # "Application"
        stack = [item.child(i) for item in top for i in range(item.childCount()) if item.child(i).text(0) == doc.Label]
        while stack:
            item = stack.pop()
            if item.text(0) == obj.Label and item.parent() is not None:
                parent = item.parent()
                while parent is not None:
                    parent.setExpanded(True)
                    parent = parent.parent()
                tree.scrollToItem(item)
                Gui.updateGui()
                return tree, item
            stack += [item.child(i) for i in range(item.childCount())]
    return None


def tree_context_menu(doc, obj):
    """Right-clicks the object in the tree as a user does; returns the texts of the menu that opens (its
    separators as "") and closes it."""
    found = tree_item(doc, obj)
    if found is None:
        return None
    tree, item = found
    at = tree.visualItemRect(item).center()
    seen = []

    def read_and_close():
        menu = QtGui.QApplication.activePopupWidget()
        if menu is None:
            return
        seen.extend("" if a.isSeparator() else a.text().replace("&", "") for a in menu.actions())
        menu.close()

    QtCore.QTimer.singleShot(300, read_and_close)
    QtGui.QApplication.sendEvent(tree.viewport(), QtGui.QMouseEvent(
        QtCore.QEvent.MouseButtonPress, at, QtCore.Qt.RightButton, QtCore.Qt.RightButton, QtCore.Qt.NoModifier))
    QtGui.QApplication.sendEvent(tree.viewport(), QtGui.QMouseEvent(
        QtCore.QEvent.MouseButtonRelease, at, QtCore.Qt.RightButton, QtCore.Qt.NoButton, QtCore.Qt.NoModifier))
    QtGui.QApplication.sendEvent(tree.viewport(), QtGui.QContextMenuEvent(
        QtGui.QContextMenuEvent.Mouse, at, tree.viewport().mapToGlobal(at)))
    Gui.updateGui()
    return seen

"""What the GUI sessions share: acting on FreeCAD's window as a user does."""
import FreeCADGui as Gui
from PySide import QtCore, QtGui


def tree_double_click(doc, obj):
    """Double-clicks the object's item under its document in the tree view, as a user does."""
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
                at = tree.visualItemRect(item).center()
                for kind in (QtCore.QEvent.MouseButtonPress, QtCore.QEvent.MouseButtonRelease,
                             QtCore.QEvent.MouseButtonDblClick, QtCore.QEvent.MouseButtonRelease):
                    buttons = QtCore.Qt.NoButton if kind == QtCore.QEvent.MouseButtonRelease else QtCore.Qt.LeftButton
                    QtGui.QApplication.sendEvent(tree.viewport(), QtGui.QMouseEvent(
                        kind, at, QtCore.Qt.LeftButton, buttons, QtCore.Qt.NoModifier))
                Gui.updateGui()
                return True
            stack += [item.child(i) for i in range(item.childCount())]
    return False

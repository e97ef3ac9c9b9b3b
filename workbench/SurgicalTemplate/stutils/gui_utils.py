"""What the workbench's commands and task panels share: icons, preferences, recorded commands,
the selection, references to objects in recorded code, the 3D view of a document, the task panels'
Qt Designer forms."""
import os

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

import SurgicalTemplate_paths
from stfunctions.presets import PREFERENCES as PREFS
from stobjects.base import kind_of


# Strings marked for translation (FreeCAD's Qt helpers, in 0.20 and 1.x): commands' menu texts and tips
# with the command's name as context, as FreeCAD translates them; the .ui forms are translated by Qt.
QT_TRANSLATE_NOOP = App.Qt.QT_TRANSLATE_NOOP
translate = App.Qt.translate


def icon(name):
    return os.path.join(SurgicalTemplate_paths.ICONS, f"SurgicalTemplate_{name}.svg")


def preference(name, default):
    """A default from the preferences page (Edit > Preferences > Surgical Template), in mm."""
    p = App.ParamGet(PREFS)
    return p.GetFloat(name, default) if name in p.GetFloats() else default


def run(title, code):
    """Runs recorded code with a wait cursor; True when it worked."""
    # Always recorded (Gui.addModule writes the import only once per session, so a macro recorded
    # later would lack it).
    code = "import SurgicalTemplate\n" + code
    QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
    progress = App.Base.ProgressIndicator()  # FreeCAD's busy indicator in the status bar
    progress.start(f"Surgical Template: {title}...", 0)
    try:
        Gui.doCommand(code)
        return True
    except Exception as e:  # the kernel's ValueError/RuntimeError name what and where
        App.Console.PrintError(f"Surgical Template: {title} failed: {e}\n")
        QtGui.QMessageBox.warning(Gui.getMainWindow(), "Surgical Template", f"{title} failed:\n{e}")
        return False
    finally:
        progress.stop()
        QtGui.QApplication.restoreOverrideCursor()


def selected(kind):
    """Selected objects of a kind: 'Bone' (a plain mesh), or a proxy kind (Boundary, Template, ...)."""
    return [o for o in Gui.Selection.getSelection() if kind_of(o) == kind]


def picked_on(kind):
    """(object, point) of the first selected object of a kind picked at a point in the 3D view (the point
    where it was clicked), else (None, None)."""
    for sel in Gui.Selection.getSelectionEx():
        if kind_of(sel.Object) == kind and sel.PickedPoints:
            return sel.Object, sel.PickedPoints[0]
    return None, None


def view_axes(doc=None):
    """The 3D view's (direction of view, up, right) as FreeCAD vectors: where the camera looks, its up
    and its right on the screen."""
    view = Gui.ActiveDocument.ActiveView if doc is None else Gui.getDocument(doc.Name).ActiveView
    rotation = view.getCameraOrientation()
    look = rotation.multVec(App.Vector(0, 0, -1))
    up = rotation.multVec(App.Vector(0, 1, 0))
    return look, up, look.cross(up)


def ref(obj):
    return f"App.getDocument({obj.Document.Name!r}).getObject({obj.Name!r})"


def view_of(doc):
    """The 3D view of a document: its active view if that is one."""
    gui_doc = Gui.getDocument(doc.Name)
    view = gui_doc.ActiveView
    if not hasattr(view, "getObjectsInfo"):
        views = gui_doc.mdiViewsOfType("Gui::View3DInventor")
        view = views[0] if views else Gui.ActiveDocument.ActiveView
    return view


def load_form(name):
    """A task panel's form from its Qt Designer file Resources/ui/<name>.ui."""
    return Gui.PySideUic.loadUi(os.path.join(SurgicalTemplate_paths.UI, f"{name}.ui"))


def leave_edit(obj):
    """Ends `obj`'s edit mode in the GUI, if it is the object in edit (a panel opened by double-click)."""
    if obj is None:
        return
    try:
        gui_doc = Gui.getDocument(obj.Document.Name)
        vp = gui_doc.getInEdit()
        if vp is not None and vp.Object.Name == obj.Name:
            gui_doc.resetEdit()
    except Exception:  # document or object gone
        pass


def number(field):
    """A unit field's (Gui::QuantitySpinBox) value in mm."""
    return float(field.property("rawValue"))


def set_number(field, value):
    field.setProperty("rawValue", float(value))


def expressions_of(obj):
    """{property: expression} of an object."""
    return {path.lstrip("."): e for path, e in obj.ExpressionEngine}


def changed_values(fields, values, before, typed, before_expressions):
    """The arguments of SurgicalTemplate.edit for a panel's unit fields ((key, property) pairs): a value
    changed by hand, an expression typed ("=..."), or an expression removed (None)."""
    changes = []
    for key, prop in fields:
        if typed.get(prop) != before_expressions.get(prop):
            changes.append(f"{prop}={'=' + typed[prop] if typed.get(prop) else None!r}")
        elif not typed.get(prop) and values[key] != before[prop]:
            changes.append(f"{prop}={values[key]}")
    return changes

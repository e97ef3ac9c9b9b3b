"""The Template and Guide task panels, opened by a double-click in the tree: the object's sizes in unit
fields bound to its properties (an expression typed after "=" drives it, as in the property editor), a
template's insertion (Auto, a direction from the view, None). Each change is previewed on the object
shortly after it is made (the template is redesigned, the guide rebuilt); OK records the changes as one
undo step (SurgicalTemplate.edit, set_insertion), Cancel puts the object back. Forms:
Resources/ui/template.ui and guide.ui."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore

from stobjects.template import INSERTION_MODES
from stutils.gui_utils import (changed_values, expressions_of, leave_edit, load_form, number, ref, run, set_number,
                               view_axes)

# kind: (form, [(field, property)])
FORMS = {"Template": ("template", [("thickness", "Thickness"), ("clearance", "Clearance"),
                                   ("resolution", "Resolution")]),
         "Guide": ("guide", [("tolerance", "Tolerance")])}
PREVIEW_DELAY = 400   # ms after the last change, so that typing does not redesign on every key


def edit_parameters(obj):
    """Opens the panel of a template or guide (its view provider's edit mode). False when it cannot."""
    if Gui.Control.activeDialog():
        App.Console.PrintWarning(f"Surgical Template: close the open task panel first, then edit {obj.Label}\n")
        return False
    Gui.Control.showDialog(ParameterPanel(obj))
    return True


class ParameterPanel:
    last = None  # the open panel, for scripts and tests

    def __init__(self, obj):
        ParameterPanel.last = self
        self.obj = obj
        self.kind = obj.Proxy.kind
        name, self.sizes = FORMS[self.kind]
        self.form = load_form(name)
        self.form.setWindowTitle(f"Edit {obj.Label}")
        self.fields, self.bindings = {}, {}
        self.before = {prop: getattr(obj, prop).Value for _, prop in self.sizes}
        self.before_expressions = expressions_of(obj)
        for key, prop in self.sizes:
            field = self.fields[key] = getattr(self.form, key)
            set_number(field, self.before[prop])
            self.bindings[prop] = Gui.ExpressionBinding(field)
            self.bindings[prop].bind(obj, prop)
            field.valueChanged.connect(lambda _: self.timer.start(PREVIEW_DELAY))
        self.timer = QtCore.QTimer()
        self.timer.setSingleShot(True)
        self.timer.timeout.connect(self.preview)
        self.insertion_before = None
        if self.kind == "Template":
            self.insertion_before = (obj.Insertion, App.Vector(obj.InsertionDirection))
            self.direction = App.Vector(obj.InsertionDirection)
            self.form.insertion.setCurrentIndex(INSERTION_MODES.index(obj.Insertion))
            self.form.insertion.currentIndexChanged.connect(lambda _: self.timer.start(PREVIEW_DELAY))
            self.form.from_view.clicked.connect(self.insertion_from_view)
            self.show_direction()
        else:
            self.form.parts.setText(self.parts_text())
        self.form.status.setText(getattr(obj, "Status", ""))

    def parts_text(self):
        g = self.obj
        slots, labels = g.Proxy.slots_of(g), g.Proxy.labels_of(g)
        return (f"{len(g.Tubes)} tube(s): {', '.join(t.Label for t in g.Tubes) or 'none'}; {len(slots)} saw slot(s), "
                f"{len(labels)} label(s). Double-click a tube in the tree to edit it.")

    def show_direction(self):
        d, mode = self.direction, INSERTION_MODES[self.form.insertion.currentIndex()]
        used = getattr(self.obj, "InsertionUsed", App.Vector())
        text = {"Direction": f"Direction ({d.x:.3f}, {d.y:.3f}, {d.z:.3f})",
                "Auto": (f"Least undercut: ({used.x:.3f}, {used.y:.3f}, {used.z:.3f})" if used.Length > 0
                         else "The direction with the least undercut"),
                "None": "No block-out, no removal check"}[mode]
        self.form.direction.setText(text)

    def insertion_from_view(self):
        look, _, _ = view_axes(self.obj.Document)
        self.direction = App.Vector(look).normalize()
        self.form.insertion.setCurrentIndex(INSERTION_MODES.index("Direction"))
        self.show_direction()
        self.timer.start(PREVIEW_DELAY)

    def values(self):
        return {key: number(field) for key, field in self.fields.items()}

    def preview(self):
        """The object with the panel's values (undone by Cancel, recorded by OK)."""
        bound = expressions_of(self.obj)
        for key, value in self.values().items():
            prop = dict(self.sizes)[key]
            if prop not in bound and abs(getattr(self.obj, prop).Value - value) > 1e-12:
                setattr(self.obj, prop, value)
        if self.kind == "Template":
            mode = INSERTION_MODES[self.form.insertion.currentIndex()]
            if mode != self.obj.Insertion:
                self.obj.Insertion = mode
            if mode == "Direction" and (self.obj.InsertionDirection - self.direction).Length > 1e-12:
                self.obj.InsertionDirection = self.direction
            self.show_direction()
        self.obj.Document.recompute()
        self.form.status.setText(getattr(self.obj, "Status", ""))

    def restore(self):
        """The object as it was before the panel opened."""
        self.timer.stop()
        changed = False
        for prop, value in self.before.items():
            if prop not in expressions_of(self.obj) and abs(getattr(self.obj, prop).Value - value) > 1e-12:
                setattr(self.obj, prop, value)
                changed = True
        if self.insertion_before is not None and (self.obj.Insertion, self.obj.InsertionDirection) != self.insertion_before:
            self.obj.Insertion, self.obj.InsertionDirection = self.insertion_before
            changed = True
        if changed:
            self.obj.Document.recompute()

    def accept(self):
        values = self.values()  # before closing deletes the widgets
        typed = {prop: self.fields[key].property("expression") or None for key, prop in self.sizes}
        mode = INSERTION_MODES[self.form.insertion.currentIndex()] if self.kind == "Template" else None
        Gui.Control.closeDialog()
        leave_edit(self.obj)
        self.restore()
        # The changes as recorded code: one undo step each call, in the macro.
        changes = changed_values(self.sizes, values, self.before, typed, self.before_expressions)
        code = []
        if mode is not None and (mode, self.direction if mode == "Direction" else None) != \
                (self.insertion_before[0], self.insertion_before[1] if self.insertion_before[0] == "Direction" else None):
            d = self.direction
            argument = {"Auto": "'auto'", "None": "None"}.get(mode, f"({d.x:.6f}, {d.y:.6f}, {d.z:.6f})")
            code.append(f"SurgicalTemplate.set_insertion({ref(self.obj)}, {argument})")
        if changes:
            code.append(f"SurgicalTemplate.edit({ref(self.obj)}, {', '.join(changes)})")
        if len(code) > 1:   # one undo step for both
            code = [f"with SurgicalTemplate._Step({ref(self.obj)}.Document, {'Edit ' + self.obj.Label!r}):"] + \
                ["    " + line for line in code]
        if code:
            run(f"Edit {self.obj.Label}", "\n".join(code) + "\nApp.ActiveDocument.recompute()\n")
        return True

    def reject(self):
        Gui.Control.closeDialog()
        leave_edit(self.obj)
        self.restore()
        return True

"""The drilling tube task panel: the entry clicked on the bone, the direction from the surface normal,
the view or a second point, sizes from a sleeve preset or typed in; OK adds the tube through recorded
code. Opened on an existing tube (double-click in the tree: edit_tube) it shows the tube's numbers,
previews each change on the guide, and OK records the changes as one undo step (Cancel leaves the tube
as it was). Its form is Resources/ui/tube.ui."""
import FreeCAD as App
import FreeCADGui as Gui

from stfunctions.presets import sleeve_presets
from stfunctions.query import kind_of
from stutils.gui_utils import (changed_values, expressions_of, leave_edit, load_form, number, preference, ref, run,
                               set_number, view_of)

SIZES = (("inner", "InnerDiameter"), ("outer", "OuterDiameter"), ("length", "Length"), ("offset", "Offset"))


def edit_tube(tube):
    """Opens the tube panel on an existing tube (its view provider's edit mode). False when it cannot."""
    if Gui.Control.activeDialog():
        App.Console.PrintWarning("Surgical Template: close the open task panel first, then edit the tube\n")
        return False
    guides = [o for o in tube.InList if kind_of(o) == "Guide"]
    guide = guides[0] if guides else None
    shell = guide.Shell if guide is not None else None
    bone = shell.Boundary.Bone if shell is not None and shell.Boundary is not None else None
    Gui.Control.showDialog(TubePanel(bone, guide, tube))
    return True


class TubePanel:
    """Click the entry on the bone; the direction comes from the surface normal there, the view, or a
    second click (a point along the axis, e.g. where it leaves the bone: its distance is the depth).
    Sizes from a sleeve preset or typed in."""

    last = None  # the open panel, for scripts and tests

    def __init__(self, bone, guide, tube=None):
        TubePanel.last = self
        self.bone, self.guide, self.tube = bone, guide, tube
        self.form = load_form("tube")
        self.presets = sleeve_presets()
        self.preset = self.form.preset
        for p in self.presets:
            self.preset.addItem(f"{p['name']}: {p['description']}")
        self.preset.currentIndexChanged.connect(self.apply_preset)
        self.fields = {}
        for key, default in (("inner", preference("InnerDiameter", 2.2)), ("outer", preference("OuterDiameter", 4.0)),
                             ("length", preference("Length", 5.0)), ("offset", preference("Offset", 3.0))):
            self.fields[key] = getattr(self.form, key)
            set_number(self.fields[key], default)
        self.mode = self.form.mode
        self.mode.currentIndexChanged.connect(lambda _: self.reset())
        self.entry, self.axis = self.form.entry, self.form.axis
        self.picked = None  # (entry, direction into the bone, depth or 0)
        self.view = view_of(bone.Document if bone is not None else App.ActiveDocument)
        self.callback = self.view.addEventCallback("SoMouseButtonEvent", self.on_mouse)
        if tube is not None:
            self.open_on(tube)

    def open_on(self, tube):
        """Fills the panel from an existing tube and previews each change on it, inside a transaction
        that OK or Cancel closes."""
        self.form.setWindowTitle(f"Edit tube {tube.Label}")
        self.form.keep_going.hide()
        self.bindings = {}
        for key, prop in SIZES:
            set_number(self.fields[key], getattr(tube, prop).Value)
            # The field shows the property's expression and takes one typed after "=" (FreeCAD's
            # expression editor), as the property editor does.
            self.bindings[prop] = Gui.ExpressionBinding(self.fields[key])
            self.bindings[prop].bind(tube, prop)
        self.before_expressions = expressions_of(tube)
        depth = getattr(tube, "Depth", None)
        self.picked = (App.Vector(tube.Entry), App.Vector(tube.Direction), depth.Value if depth is not None else 0.0)
        self.show_picked()
        self.before = {prop: getattr(tube, prop).Value for _, prop in SIZES}
        self.before_axis = (App.Vector(tube.Entry), App.Vector(tube.Direction))
        for key, prop in SIZES:
            self.fields[key].valueChanged.connect(lambda _, key=key, prop=prop: self.preview(prop, number(self.fields[key])))

    def preview(self, prop, value):
        """A changed size shown on the tube and its guide at once (undone by Cancel, recorded by OK); a
        size an expression drives follows it."""
        if prop in expressions_of(self.tube) or abs(getattr(self.tube, prop).Value - value) < 1e-12:
            return
        setattr(self.tube, prop, value)
        self.tube.Document.recompute()

    def restore(self):
        """The tube as it was before the panel opened."""
        for prop, value in self.before.items():
            setattr(self.tube, prop, value)
        self.tube.Entry, self.tube.Direction = self.before_axis
        self.tube.Document.recompute()

    def apply_preset(self, index):
        if index <= 0:
            return
        p = self.presets[index - 1]
        for key, field, times in (("inner", "inner_radius", 2.0), ("outer", "outer_radius", 2.0),
                                  ("length", "length", 1.0), ("offset", "offset", 1.0)):
            set_number(self.fields[key], times * p[field])

    def reset(self):
        self.picked = None
        self.entry.setText("click the entry point on the bone")
        self.axis.setText("")

    def on_mouse(self, info):
        if info.get("State") == "DOWN" and info.get("Button") == "BUTTON1":
            self.click(info["Position"])

    def _hit(self, position):
        hit = self.view.getObjectInfo(tuple(position))
        if not hit or self.bone is None or hit.get("Object") != self.bone.Name:
            return None, None
        p = App.Vector(hit["x"], hit["y"], hit["z"])
        # The clicked facet (FreeCAD names a mesh pick only "Main"): the first one a short ray along the
        # view meets through the picked point.
        d = App.Vector(self.view.getViewDirection())
        facets = self.bone.Mesh.nearestFacetOnRay(tuple(p - d * 0.05), tuple(d))
        normal = self.bone.Mesh.Facets[int(list(facets)[0])].Normal if facets else None
        return p, normal

    def click(self, position):
        """A click at a screen position: the entry, or in second-point mode the point along the axis."""
        p, normal = self._hit(position)
        if p is None:
            return False
        mode = self.mode.currentIndex()
        if mode == 2 and self.picked is not None and self.picked[2] == 0 and self.picked[1] is None:
            along = p - self.picked[0]
            if along.Length < 1e-6:
                return False
            self.picked = (self.picked[0], along.normalize(), (p - self.picked[0]).Length)
        else:
            if mode == 0:
                d = (normal if normal is not None else self.view.getViewDirection() * -1) * -1
            elif mode == 1:
                d = App.Vector(self.view.getViewDirection())
            else:
                d = None  # wait for the second point
            self.picked = (p, d, 0.0)
        self.show_picked()
        return True

    def show_picked(self):
        p, d, depth = self.picked
        self.entry.setText(f"{p.x:.2f}, {p.y:.2f}, {p.z:.2f}")
        self.axis.setText("click a second point along the axis" if d is None else
                          f"direction {d.x:.3f}, {d.y:.3f}, {d.z:.3f}" + (f"; depth {depth:.1f} mm" if depth else ""))

    def accept(self):
        f = {k: number(v) for k, v in self.fields.items()}  # before closing deletes the widgets
        typed = {prop: self.fields[key].property("expression") or None for key, prop in SIZES} \
            if self.tube is not None else {}
        index = self.preset.currentIndex()
        preset = self.presets[index - 1]["name"] if index > 0 else ""
        if self.tube is None and self.form.keep_going.isChecked() and self.picked is not None \
                and self.picked[1] is not None:
            self.add_tube(f, preset)   # and the panel stays open for the next one
            self.reset()
            return False
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        leave_edit(self.tube)
        if self.picked is None or self.picked[1] is None:
            if self.tube is not None:
                self.restore()
            return True
        p, d, depth = self.picked
        if self.tube is not None:
            # The preview undone, then the changes as recorded code: one undo step, in the macro.
            self.restore()
            changes = changed_values(SIZES, f, self.before, typed, self.before_expressions)
            if (p, d) != self.before_axis:
                changes += [f"Entry=({p.x:.4f}, {p.y:.4f}, {p.z:.4f})", f"Direction=({d.x:.5f}, {d.y:.5f}, {d.z:.5f})"]
            if changes:
                run("Edit drilling tube", f"SurgicalTemplate.edit_tube({ref(self.tube)}, {', '.join(changes)})")
            return True
        self.add_tube(f, preset)
        return True

    def add_tube(self, f, preset):
        """The picked tube with the panel's sizes, through recorded code (one undo step)."""
        p, d, depth = self.picked
        code = (f"tube = SurgicalTemplate.make_tube(({p.x:.4f}, {p.y:.4f}, {p.z:.4f}), ({d.x:.5f}, {d.y:.5f}, "
                f"{d.z:.5f}), length={f['length']}, offset={f['offset']}, inner_diameter={f['inner']}, "
                f"outer_diameter={f['outer']}"
                + (f", depth={depth:.3f}" if depth else "") + (f", preset={preset!r}" if preset else "")
                + (f", guide={ref(self.guide)}" if self.guide is not None else "") + ")\n")
        run("Add drilling tube", code + "App.ActiveDocument.recompute()")

    def reject(self):
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        leave_edit(self.tube)
        if self.tube is not None:
            self.restore()
        return True

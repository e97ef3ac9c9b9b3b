"""The workbench's design commands, in the order of the work: draw a boundary on the bone, create the
template, add drilling tubes, create the guide, add saw slots and labels to it, validate it. The first opens its task panel; the others
run recorded code through the API (SurgicalTemplate.py), one undo step each."""
import FreeCAD as App
import FreeCADGui as Gui

from stcommands.base import Command
from stfunctions.presets import preferred_slot
from stfunctions.query import tree_of
from sttaskpanels.boundary import BoundaryPanel
from sttaskpanels.tube import TubePanel
from sttaskpanels.validate import ValidatePanel
from stutils.gui_utils import QT_TRANSLATE_NOOP, picked_on, preference, ref, run, selected, view_axes


class CreateTemplate(Command):
    name, menu = "CreateTemplate", QT_TRANSLATE_NOOP("SurgicalTemplate_CreateTemplate", "Create template")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_CreateTemplate",
                            "Design the template shell inside the selected boundary (thickness and "
                            "clearance from the preferences)")

    def IsActive(self):
        return bool(selected("Boundary"))

    def Activated(self):
        b = selected("Boundary")[0]
        run("Create template",
            f"SurgicalTemplate.make_template({ref(b)}, thickness={preference('Thickness', 2.5)}, "
            f"clearance={preference('Clearance', 0.0)}, resolution={preference('Resolution', 0.0)})\n"
            "App.ActiveDocument.recompute()")


class InsertionFromView(Command):
    name, menu = "InsertionFromView", QT_TRANSLATE_NOOP("SurgicalTemplate_InsertionFromView", "Insertion from view")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_InsertionFromView",
                            "Set the selected template's insertion direction to the 3D view's: the "
                            "guide moves onto the bone the way you look at it; undercuts along it are"
                            " blocked out and the guide checked to come off")

    def IsActive(self):
        return bool(selected("Template")) and Gui.ActiveDocument is not None

    def Activated(self):
        shell = selected("Template")[0]
        d = Gui.ActiveDocument.ActiveView.getViewDirection()
        run("Insertion from view", f"SurgicalTemplate.set_insertion({ref(shell)}, ({d.x:.6f}, {d.y:.6f}, {d.z:.6f}))\n"
                                   "App.ActiveDocument.recompute()")


class CreateGuide(Command):
    name, menu = "CreateGuide", QT_TRANSLATE_NOOP("SurgicalTemplate_CreateGuide", "Create surgical guide")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_CreateGuide",
                            "Merge the selected drilling tubes into the selected template and cut "
                            "their bores")

    def IsActive(self):
        return bool(selected("Template"))

    def Activated(self):
        shell = selected("Template")[0]
        tubes = ", ".join(ref(t) for t in selected("Tube"))
        run("Create surgical guide", f"SurgicalTemplate.make_guide({ref(shell)}, [{tubes}])\n"
                                     "App.ActiveDocument.recompute()")


class Validate(Command):
    name, menu = "Validate", QT_TRANSLATE_NOOP("SurgicalTemplate_Validate", "Validate")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_Validate",
                            "Inspect the selected guide or template: printable solid, seating on the "
                            "bone, every bore open; colours it by the distance from the bone "
                            "(thickness map)")

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        Gui.Control.showDialog(ValidatePanel(obj))


class DrawBoundary(Command):
    name, menu = "DrawBoundary", QT_TRANSLATE_NOOP("SurgicalTemplate_DrawBoundary", "Draw boundary")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_DrawBoundary",
                            "Click control points around the region on the selected bone; the curve "
                            "on the surface follows live. Drag a point to move it, Delete removes the"
                            " selected ones; finish with OK (Enter). Double-click a boundary in the "
                            "tree to edit its points")

    def IsActive(self):
        return bool(selected("Bone"))

    def Activated(self):
        Gui.Control.showDialog(BoundaryPanel(selected("Bone")[0]))


class AddTube(Command):
    name, menu = "AddTube", QT_TRANSLATE_NOOP("SurgicalTemplate_AddTube", "Add drilling tube")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_AddTube",
                            "Add a guide sleeve: click its entry on the bone (direction: into the "
                            "bone along the surface normal), set its diameters and length; added to "
                            "the selected guide")

    def Activated(self):
        chosen = (selected("Guide") or selected("Template") or selected("Boundary") or selected("Bone") or [None])[0]
        if chosen is not None:
            guide, _, _, bone = tree_of(chosen)
        else:
            bones = [o for o in App.ActiveDocument.Objects if o.TypeId == "Mesh::Feature"]
            guide, bone = None, bones[-1] if bones else None
        Gui.Control.showDialog(TubePanel(bone, guide))


def _vec(v):
    return f"({v.x:.6f}, {v.y:.6f}, {v.z:.6f})"


class _AtPickedPoint(Command):
    """A command on the guide at the point where it was clicked, with the 3D view's axes; subclasses give
    the title and the recorded call (code)."""

    title = ""

    def IsActive(self):
        return picked_on("Guide")[0] is not None and Gui.ActiveDocument is not None

    def Activated(self):
        guide, point = picked_on("Guide")
        run(self.title, self.code(ref(guide), _vec(point), *(_vec(v) for v in view_axes())))


class AddLabel(_AtPickedPoint):
    name, menu, title = "AddLabel", QT_TRANSLATE_NOOP("SurgicalTemplate_AddLabel", "Add label"), "Add label"
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_AddLabel",
                            "Engrave a label into the guide where you clicked it: the case's name by "
                            "default, reading across the 3D view (its up the view's up); cap height "
                            "and depth from the preferences. Edit it as the Label object under the guide")

    def code(self, guide, at, look, up, right):
        return (f"SurgicalTemplate.add_label({guide}, {at}, {up}, height={preference('LabelHeight', 4.0)}, "
                f"depth={preference('LabelDepth', 0.6)})")


class AddSlot(_AtPickedPoint):
    name, menu, title = "AddSlot", QT_TRANSLATE_NOOP("SurgicalTemplate_AddSlot", "Add saw slot from view"), "Add saw slot"
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_AddSlot",
                            "Add a saw slot where you clicked the guide: the saw travels the way you "
                            "look, the cut plane holds the view's up (it shows as a vertical line); "
                            "blade and length from the preferences. Edit it as the Slot object under the guide (its BladePreset "
                            "chooses a blade)")

    def code(self, guide, origin, look, up, right):
        blade, length = preferred_slot()
        return f"SurgicalTemplate.add_slot({guide}, {origin}, {right}, {look}, blade={blade}, length={length})"

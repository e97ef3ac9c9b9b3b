"""The workbench's design commands, in the order of the work: draw a boundary on the bone, create the
template, add drilling tubes, create the guide, validate it. The first opens its task panel; the others
run recorded code through the API (SurgicalTemplate.py), one undo step each."""
import FreeCAD as App
import FreeCADGui as Gui

from stcommands.base import Command
from stfunctions.query import tree_of
from sttaskpanels.boundary import BoundaryPanel
from sttaskpanels.tube import TubePanel
from sttaskpanels.validate import ValidatePanel
from stutils.gui_utils import preference, ref, run, selected


class CreateTemplate(Command):
    name, menu = "CreateTemplate", "Create template"
    tip = "Design the template shell inside the selected boundary (thickness and clearance from the preferences)"

    def IsActive(self):
        return bool(selected("Boundary"))

    def Activated(self):
        b = selected("Boundary")[0]
        run("Create template",
            f"SurgicalTemplate.make_template({ref(b)}, thickness={preference('Thickness', 2.5)}, "
            f"clearance={preference('Clearance', 0.0)}, resolution={preference('Resolution', 0.0)})\n"
            "App.ActiveDocument.recompute()")


class InsertionFromView(Command):
    name, menu = "InsertionFromView", "Insertion from view"
    tip = ("Set the selected template's insertion direction to the 3D view's: the guide moves onto the bone the "
           "way you look at it; undercuts along it are blocked out and the guide checked to come off")

    def IsActive(self):
        return bool(selected("Template")) and Gui.ActiveDocument is not None

    def Activated(self):
        shell = selected("Template")[0]
        d = Gui.ActiveDocument.ActiveView.getViewDirection()
        run("Insertion from view", f"SurgicalTemplate.set_insertion({ref(shell)}, ({d.x:.6f}, {d.y:.6f}, {d.z:.6f}))\n"
                                   "App.ActiveDocument.recompute()")


class CreateGuide(Command):
    name, menu = "CreateGuide", "Create surgical guide"
    tip = "Merge the selected drilling tubes into the selected template and cut their bores"

    def IsActive(self):
        return bool(selected("Template"))

    def Activated(self):
        shell = selected("Template")[0]
        tubes = ", ".join(ref(t) for t in selected("Tube"))
        run("Create surgical guide", f"SurgicalTemplate.make_guide({ref(shell)}, [{tubes}])\n"
                                     "App.ActiveDocument.recompute()")


class Validate(Command):
    name, menu = "Validate", "Validate"
    tip = ("Inspect the selected guide or template: printable solid, seating on the bone, every bore open; "
           "colours it by the distance from the bone (thickness map)")

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        Gui.Control.showDialog(ValidatePanel(obj))


class DrawBoundary(Command):
    name, menu = "DrawBoundary", "Draw boundary"
    tip = ("Click control points around the region on the selected bone; the curve on the surface follows "
           "live. Drag a point to move it, Delete removes the selected ones; finish with OK (Enter). "
           "Double-click a boundary in the tree to edit its points")

    def IsActive(self):
        return bool(selected("Bone"))

    def Activated(self):
        Gui.Control.showDialog(BoundaryPanel(selected("Bone")[0]))


class AddTube(Command):
    name, menu = "AddTube", "Add drilling tube"
    tip = ("Add a guide sleeve: click its entry on the bone (direction: into the bone along the surface normal), "
           "set radii and length; added to the selected guide")

    def Activated(self):
        chosen = (selected("Guide") or selected("Template") or selected("Boundary") or selected("Bone") or [None])[0]
        if chosen is not None:
            guide, _, _, bone = tree_of(chosen)
        else:
            bones = [o for o in App.ActiveDocument.Objects if o.TypeId == "Mesh::Feature"]
            guide, bone = None, bones[-1] if bones else None
        Gui.Control.showDialog(TubePanel(bone, guide))

"""GUI commands of the Surgical Template workbench (their task panels are in st_panels.py).

Every change goes through Gui.doCommand, so the macro recorder writes a script that replays it, and
through the API (SurgicalTemplate.py), so each change is one undo step. Failures are reported in the
Report view and a message box; the document keeps its last good state.
"""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

import st_bridge
from st_gui import icon, preference, ref, run, selected
from st_panels import BoundaryPanel, TubePanel, ValidatePanel, edit_boundary  # noqa: F401 (scripts use them here)


class _Command:
    name = ""
    menu = ""
    tip = ""
    needs_document = True

    def GetResources(self):
        return {"Pixmap": icon(self.name), "MenuText": self.menu, "ToolTip": self.tip}

    def IsActive(self):
        return App.ActiveDocument is not None or not self.needs_document


class ImportBone(_Command):
    name, menu = "ImportBone", "Import bone"
    tip = "Import a bone or dentition scan (STL, PLY, OBJ, also .gz) as the bone of a template"
    needs_document = False

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(Gui.getMainWindow(), "Import bone", "",
                                                    "Meshes (*.stl *.STL *.ply *.obj *.gz);;All files (*)")
        if path:
            import_bone(path)


def import_bone(path):
    """The command after its file dialog: the bone into the active document (a new one if none)."""
    code = "App.newDocument('SurgicalTemplate')\n" if App.ActiveDocument is None else ""
    ok = run("Import bone", code + f"SurgicalTemplate.make_bone({path!r})\nApp.ActiveDocument.recompute()")
    if ok:
        Gui.SendMsgToActiveView("ViewFit")
    return ok


class OpenCase(_Command):
    name, menu = "OpenCase", "Open case file"
    tip = "Build the whole guide (bone, boundary, template, tubes) from a case file (surgical-template-case/1)"
    needs_document = False

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(Gui.getMainWindow(), "Open case", "", "Case files (*.json)")
        if path:
            open_case(path)


def open_case(path):
    ok = run("Open case", f"guide = SurgicalTemplate.load_case({path!r})")
    if ok:
        Gui.SendMsgToActiveView("ViewFit")
    return ok


class ImportPlan(_Command):
    name, menu = "ImportPlan", "Import plan"
    tip = ("Import a surgical plan onto the selected guide, template, boundary or bone: 3D Slicer markups "
           "(.mrk.json: ClosedCurve boundary, Line axes; LPS or RAS), a CSV of axes, or a case file")

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(
            Gui.getMainWindow(), "Import plan", "",
            "Plans (*.mrk.json *.json *.csv *.tsv *.txt);;3D Slicer markups (*.mrk.json);;CSV (*.csv *.tsv *.txt)")
        if path:
            target = (selected("Guide") or selected("Template") or selected("Boundary") or selected("Bone") or [None])[0]
            import_plan(path, target, ask_preset)


def ask_preset(axes):
    """The sleeve preset for axes whose plan gives no sizes, chosen by the user; None to cancel."""
    import SurgicalTemplate
    names = [f"{p['name']}: {p['description']}" for p in SurgicalTemplate.sleeve_presets()]
    choice, ok = QtGui.QInputDialog.getItem(
        Gui.getMainWindow(), "Sleeve preset",
        f"{len(axes)} axis(es) have no sleeve sizes in the plan. Sleeve for them:", names, 0, False)
    return choice.split(":")[0] if ok else None


def import_plan(path, target, choose_preset):
    """Imports a plan through recorded code; asks `choose_preset(axes)` when axes lack sizes."""
    import SurgicalTemplate
    preset = None
    try:
        bone = SurgicalTemplate.tree_of(target)[3] if target is not None else None
        plan = st_bridge.kernel().read_plan(path, getattr(bone, "CoordinateSystem", "LPS"))
    except (ValueError, RuntimeError) as e:
        App.Console.PrintError(f"Surgical Template: Import plan failed: {e}\n")
        QtGui.QMessageBox.warning(Gui.getMainWindow(), "Surgical Template", f"Import plan failed:\n{e}")
        return False
    unsized = [a for a in plan["axes"] if a["inner_radius"] is None or a["outer_radius"] is None or a["length"] is None]
    if unsized:
        preset = choose_preset(unsized)
        if preset is None:
            return False
    target_code = ref(target) if target is not None else "None"
    ok = run("Import plan", f"guide = SurgicalTemplate.load_plan({path!r}, {target_code}, preset={preset!r})")
    if ok:
        Gui.SendMsgToActiveView("ViewFit")
    return ok


class MakeDrawing(_Command):
    name, menu = "Drawing", "Documentation drawing"
    tip = ("Make the selected guide's drawing: views, each sleeve dimensioned, sleeve table; "
           "exported as PDF and SVG with a drill protocol (.txt)")

    def IsActive(self):
        return bool(selected("Guide"))

    def Activated(self):
        guide = selected("Guide")[0]
        path, _ = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Documentation drawing",
                                                    guide.Label + ".pdf", "PDF (*.pdf)")
        if path:
            run("Documentation drawing", f"SurgicalTemplate.make_drawing({ref(guide)}, {path!r})")


class SaveCase(_Command):
    name, menu = "SaveCase", "Save case file"
    tip = "Write the selected guide's plan as a case file"

    def IsActive(self):
        return bool(selected("Guide"))

    def Activated(self):
        guide = selected("Guide")[0]
        path, _ = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Save case", guide.Label + ".json",
                                                    "Case files (*.json)")
        if path:
            run("Save case", f"SurgicalTemplate.save_case({ref(guide)}, {path!r})")


class CreateTemplate(_Command):
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


class CreateGuide(_Command):
    name, menu = "CreateGuide", "Create surgical guide"
    tip = "Merge the selected drilling tubes into the selected template and cut their bores"

    def IsActive(self):
        return bool(selected("Template"))

    def Activated(self):
        shell = selected("Template")[0]
        tubes = ", ".join(ref(t) for t in selected("Tube"))
        run("Create surgical guide", f"SurgicalTemplate.make_guide({ref(shell)}, [{tubes}])\n"
                                     "App.ActiveDocument.recompute()")


class ExportSTL(_Command):
    name, menu = "ExportSTL", "Export STL"
    tip = "Write the selected template or guide as a binary STL for printing"

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        path, _ = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Export STL", obj.Label + ".stl",
                                                    "STL (*.stl)")
        if path:
            run("Export STL", f"SurgicalTemplate.export({ref(obj)}, {path!r})")


class Validate(_Command):
    name, menu = "Validate", "Validate"
    tip = ("Inspect the selected guide or template: printable solid, seating on the bone, every bore open; "
           "colours it by the distance from the bone (thickness map)")

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        Gui.Control.showDialog(ValidatePanel(obj))


class DrawBoundary(_Command):
    name, menu = "DrawBoundary", "Draw boundary"
    tip = ("Click control points around the region on the selected bone; the curve on the surface follows "
           "live. Drag a point to move it, Delete removes the selected ones; finish with OK (Enter). "
           "Double-click a boundary in the tree to edit its points")

    def IsActive(self):
        return bool(selected("Bone"))

    def Activated(self):
        Gui.Control.showDialog(BoundaryPanel(selected("Bone")[0]))


class AddTube(_Command):
    name, menu = "AddTube", "Add drilling tube"
    tip = ("Add a guide sleeve: click its entry on the bone (direction: into the bone along the surface normal), "
           "set radii and length; added to the selected guide")

    def Activated(self):
        import SurgicalTemplate
        chosen = (selected("Guide") or selected("Template") or selected("Boundary") or selected("Bone") or [None])[0]
        if chosen is not None:
            guide, _, _, bone = SurgicalTemplate.tree_of(chosen)
        else:
            bones = [o for o in App.ActiveDocument.Objects if o.TypeId == "Mesh::Feature"]
            guide, bone = None, bones[-1] if bones else None
        Gui.Control.showDialog(TubePanel(bone, guide))


COMMANDS = {
    "SurgicalTemplate_OpenCase": OpenCase(),
    "SurgicalTemplate_ImportPlan": ImportPlan(),
    "SurgicalTemplate_SaveCase": SaveCase(),
    "SurgicalTemplate_ImportBone": ImportBone(),
    "SurgicalTemplate_DrawBoundary": DrawBoundary(),
    "SurgicalTemplate_CreateTemplate": CreateTemplate(),
    "SurgicalTemplate_AddTube": AddTube(),
    "SurgicalTemplate_CreateGuide": CreateGuide(),
    "SurgicalTemplate_Validate": Validate(),
    "SurgicalTemplate_ExportSTL": ExportSTL(),
    "SurgicalTemplate_Drawing": MakeDrawing(),
}


def register():
    for name, command in COMMANDS.items():
        Gui.addCommand(name, command)
    return list(COMMANDS)

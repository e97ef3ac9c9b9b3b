"""The workbench's file commands: open a case, import a bone or a plan, save the case, export for
printing (3MF, STL, OBJ) or the sleeves (STEP), make the documentation drawing. Every change is
recorded code through the API (SurgicalTemplate.py), so the macro recorder writes a script that replays
it and each change is one undo step."""
import os

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtGui

import st_bridge
import SurgicalTemplate_paths
from stcommands.base import Command
from stfunctions.presets import preferred_slot, sleeve_presets
from stfunctions.query import tree_of
from stutils.gui_utils import QT_TRANSLATE_NOOP, ref, run, selected


class ImportBone(Command):
    name, menu = "ImportBone", QT_TRANSLATE_NOOP("SurgicalTemplate_ImportBone", "Import bone")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_ImportBone",
                            "Import a bone or dentition scan (STL, PLY, OBJ, also .gz) as the bone of"
                            " a template")
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


class OpenCase(Command):
    name, menu = "OpenCase", QT_TRANSLATE_NOOP("SurgicalTemplate_OpenCase", "Open case file")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_OpenCase",
                            "Build the whole guide (bone, boundary, template, tubes) from a case file"
                            " (surgical-template-case/1)")
    needs_document = False

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(Gui.getMainWindow(), "Open case", "", "Case files (*.json)")
        if path:
            open_case(path)


def example_cases():
    """{command name: case file} of the example cases installed with the workbench, by file name."""
    folder = os.path.join(SurgicalTemplate_paths.EXAMPLES, "cases")
    names = sorted(f for f in os.listdir(folder) if f.endswith(".json")) if os.path.isdir(folder) else []
    return {"SurgicalTemplate_Example_" + os.path.splitext(f)[0].replace("-", "_"): os.path.join(folder, f)
            for f in names}


class OpenExample(Command):
    """The "Open example" submenu: one command per example case (ExampleCase)."""
    name, menu = "OpenExample", QT_TRANSLATE_NOOP("SurgicalTemplate_OpenExample", "Open example")
    pixmap = "OpenCase"
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_OpenExample",
                            "Open one of the example cases installed with the workbench: its bone, plan"
                            " and guide")
    needs_document = False

    def GetCommands(self):
        return tuple(example_cases())

    def GetResources(self):
        return dict(super().GetResources(), DropDownMenu=True, Exclusive=False)


class ExampleCase(Command):
    """Opens one example case (its file name is its menu text)."""
    pixmap = "OpenCase"
    needs_document = False

    def __init__(self, path):
        self.path = path
        self.menu = os.path.splitext(os.path.basename(path))[0]
        self.tip = f"Open the example case {self.menu} ({path})"

    def Activated(self):
        open_case(self.path)


def open_case(path):
    ok = run("Open case", f"guide = SurgicalTemplate.load_case({path!r})")
    if ok:
        Gui.SendMsgToActiveView("ViewFit")
    return ok


class ImportPlan(Command):
    name, menu = "ImportPlan", QT_TRANSLATE_NOOP("SurgicalTemplate_ImportPlan", "Import plan")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_ImportPlan",
                            "Import a surgical plan onto the selected guide, template, boundary or "
                            "bone: 3D Slicer markups (.mrk.json: ClosedCurve boundary, Line axes; LPS"
                            " or RAS), a CSV of axes, or a case file")

    def Activated(self):
        path, _ = QtGui.QFileDialog.getOpenFileName(
            Gui.getMainWindow(), "Import plan", "",
            "Plans (*.mrk.json *.json *.csv *.tsv *.txt);;3D Slicer markups (*.mrk.json);;CSV (*.csv *.tsv *.txt)")
        if path:
            target = (selected("Guide") or selected("Template") or selected("Boundary") or selected("Bone") or [None])[0]
            import_plan(path, target, ask_preset)


def ask_preset(axes):
    """The sleeve preset for axes whose plan gives no sizes, chosen by the user; None to cancel."""
    names = [f"{p['name']}: {p['description']}" for p in sleeve_presets()]
    choice, ok = QtGui.QInputDialog.getItem(
        Gui.getMainWindow(), "Sleeve preset",
        f"{len(axes)} axis(es) have no sleeve sizes in the plan. Sleeve for them:", names, 0, False)
    return choice.split(":")[0] if ok else None


def import_plan(path, target, choose_preset):
    """Imports a plan through recorded code; asks `choose_preset(axes)` when axes lack sizes."""
    preset = None
    try:
        bone = tree_of(target)[3] if target is not None else None
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
    # Planes without a blade or a length take the preferences' (as Add saw slot does).
    blade, length = preferred_slot()
    blade = blade if any(p["blade"] is None for p in plan["planes"]) else None
    length = length if any(p["length"] is None for p in plan["planes"]) else None
    target_code = ref(target) if target is not None else "None"
    ok = run("Import plan", f"guide = SurgicalTemplate.load_plan({path!r}, {target_code}, preset={preset!r}, "
                            f"blade={blade!r}, slot_length={length!r})")
    if ok:
        Gui.SendMsgToActiveView("ViewFit")
    return ok


class MakeDrawing(Command):
    name, menu = "Drawing", QT_TRANSLATE_NOOP("SurgicalTemplate_Drawing", "Documentation drawing")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_Drawing",
                            "Make the selected guide's drawing: views, each sleeve dimensioned, "
                            "sleeve table; exported as PDF and SVG with a drill protocol (.txt)")

    def IsActive(self):
        return bool(selected("Guide"))

    def Activated(self):
        guide = selected("Guide")[0]
        path, _ = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Documentation drawing",
                                                    guide.Label + ".pdf", "PDF (*.pdf)")
        if path:
            run("Documentation drawing", f"SurgicalTemplate.make_drawing({ref(guide)}, {path!r})")


class SaveCase(Command):
    name, menu = "SaveCase", QT_TRANSLATE_NOOP("SurgicalTemplate_SaveCase", "Save case file")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_SaveCase",
                            "Write the selected guide's plan as a case file")

    def IsActive(self):
        return bool(selected("Guide"))

    def Activated(self):
        guide = selected("Guide")[0]
        path, _ = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Save case", guide.Label + ".json",
                                                    "Case files (*.json)")
        if path:
            run("Save case", f"SurgicalTemplate.save_case({ref(guide)}, {path!r})")


class ExportSTL(Command):
    name, menu = "ExportSTL", QT_TRANSLATE_NOOP("SurgicalTemplate_ExportSTL", "Export for printing")
    tip = QT_TRANSLATE_NOOP("SurgicalTemplate_ExportSTL",
                            "Write the selected template or guide for printing: 3MF (units kept; "
                            "printers prefer it), STL or OBJ; or a guide's sleeves as STEP solids for"
                            " CAD")
    FILTERS = {"3MF (*.3mf)": ".3mf", "STL (*.stl)": ".stl", "OBJ (*.obj)": ".obj",
               "STEP of the sleeves (*.step *.stp)": ".step"}

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        path, chosen = QtGui.QFileDialog.getSaveFileName(Gui.getMainWindow(), "Export", obj.Label + ".3mf",
                                                         ";;".join(self.FILTERS))
        if path:
            if not os.path.splitext(path)[1]:
                path += self.FILTERS.get(chosen, ".3mf")
            run("Export", f"SurgicalTemplate.export({ref(obj)}, {path!r})")

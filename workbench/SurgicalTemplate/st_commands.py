"""GUI commands and task panels of the Surgical Template workbench.

Every change goes through Gui.doCommand, so the macro recorder writes a script that replays it, and
through the API (SurgicalTemplate.py), so each change is one undo step. Failures are reported in the
Report view and a message box; the document keeps its last good state.
"""
import os

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

import st_bridge

ICONS = os.path.join(os.path.dirname(os.path.abspath(__file__)), "icons")
PREFS = "User parameter:BaseApp/Preferences/Mod/SurgicalTemplate"


def icon(name):
    return os.path.join(ICONS, f"SurgicalTemplate_{name}.svg")


def preference(name, default):
    """A default from the preferences page (Edit > Preferences > Surgical Template), in mm."""
    p = App.ParamGet(PREFS)
    return p.GetFloat(name, default) if name in p.GetFloats() else default


def run(title, code):
    """Runs recorded code with a wait cursor; True when it worked."""
    Gui.addModule("SurgicalTemplate")
    QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
    try:
        Gui.doCommand(code)
        return True
    except Exception as e:  # the kernel's ValueError/RuntimeError name what and where
        App.Console.PrintError(f"Surgical Template: {title} failed: {e}\n")
        QtGui.QMessageBox.warning(Gui.getMainWindow(), "Surgical Template", f"{title} failed:\n{e}")
        return False
    finally:
        QtGui.QApplication.restoreOverrideCursor()


def selected(kind):
    """Selected objects of a kind: 'Bone' (a plain mesh), or a proxy kind (Boundary, Template, ...)."""
    out = []
    for o in Gui.Selection.getSelection():
        proxy_kind = getattr(getattr(o, "Proxy", None), "kind", None)
        if kind == "Bone" and o.TypeId == "Mesh::Feature":
            out.append(o)
        elif proxy_kind == kind:
            out.append(o)
    return out


def ref(obj):
    return f"App.getDocument({obj.Document.Name!r}).getObject({obj.Name!r})"


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
            if App.ActiveDocument is None:
                App.newDocument("SurgicalTemplate")
            run("Import bone", f"SurgicalTemplate.make_bone({path!r})\nApp.ActiveDocument.recompute()")
            Gui.SendMsgToActiveView("ViewFit")


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
    tip = "Check the selected template or guide: closed, 2-manifold, outward, self-intersection free, one piece"

    def IsActive(self):
        return bool(selected("Guide") or selected("Template"))

    def Activated(self):
        obj = (selected("Guide") or selected("Template"))[0]
        k = st_bridge.kernel()
        report = k.check_solid(*st_bridge.mesh_to_arrays(obj.Mesh))
        text = f"{obj.Label}: {report['summary']}"
        (App.Console.PrintMessage if report["valid"] else App.Console.PrintError)(f"Surgical Template: {text}\n")
        QtGui.QMessageBox.information(Gui.getMainWindow(), "Surgical Template", text)


class DrawBoundary(_Command):
    name, menu = "DrawBoundary", "Draw boundary"
    tip = ("Click control points around the region on the selected bone; the curve on the surface follows "
           "live. Finish with OK (Enter)")

    def IsActive(self):
        return bool(selected("Bone"))

    def Activated(self):
        Gui.Control.showDialog(BoundaryPanel(selected("Bone")[0]))


class BoundaryPanel:
    """Clicks on the bone add control points; the curve through them is shown as it is computed."""

    last = None  # the open panel, for scripts and tests

    def __init__(self, bone):
        BoundaryPanel.last = self
        self.bone = bone
        self.points = []
        self.preview = None
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Boundary")
        layout = QtGui.QVBoxLayout(self.form)
        layout.addWidget(QtGui.QLabel(f"Click points around the region on '{bone.Label}', in order."))
        self.list = QtGui.QListWidget()
        layout.addWidget(self.list)
        row = QtGui.QHBoxLayout()
        remove = QtGui.QPushButton("Remove selected")
        remove.clicked.connect(self.remove_selected)
        clear = QtGui.QPushButton("Clear")
        clear.clicked.connect(self.clear)
        row.addWidget(remove)
        row.addWidget(clear)
        layout.addLayout(row)
        self.status = QtGui.QLabel("")
        layout.addWidget(self.status)
        self.view = Gui.ActiveDocument.ActiveView
        self.callback = self.view.addEventCallback("SoMouseButtonEvent", self.on_mouse)

    def on_mouse(self, info):
        if info.get("State") != "DOWN" or info.get("Button") != "BUTTON1" or info.get("CtrlDown"):
            return
        self.click(info["Position"])

    def click(self, position):
        """A click at a screen position: a point where it meets the bone."""
        hit = self.view.getObjectInfo(tuple(position))
        if not hit or hit.get("Object") != self.bone.Name:
            return False
        self.points.append(App.Vector(hit["x"], hit["y"], hit["z"]))
        self.update()
        return True

    def remove_selected(self):
        for row in sorted((self.list.row(i) for i in self.list.selectedItems()), reverse=True):
            del self.points[row]
        self.update()

    def clear(self):
        self.points = []
        self.update()

    def update(self):
        self.list.clear()
        for i, p in enumerate(self.points):
            self.list.addItem(f"{i + 1}: {p.x:.2f}, {p.y:.2f}, {p.z:.2f}")
        if len(self.points) < 3:
            self.status.setText(f"{len(self.points)} point(s): at least 3 needed")
            if self.preview is not None:
                self.preview.Points = []
            return
        if self.preview is None:
            import SurgicalTemplate
            self.preview = SurgicalTemplate.make_boundary(self.bone, self.points, name="BoundaryPreview")
        self.preview.Points = self.points
        try:
            self.preview.recompute()
            self.status.setText(f"{len(self.points)} points; curve {self.preview.Shape.Length:.1f} mm")
        except Exception as e:
            self.status.setText(f"no curve: {e}")

    def finish(self):
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        if self.preview is not None:
            self.preview.Document.removeObject(self.preview.Name)
            self.preview = None

    def accept(self):
        points = [(round(p.x, 4), round(p.y, 4), round(p.z, 4)) for p in self.points]
        self.finish()
        Gui.Control.closeDialog()
        if len(points) >= 3:
            run("Create boundary", f"SurgicalTemplate.make_boundary({ref(self.bone)}, {points})\n"
                                   "App.ActiveDocument.recompute()")
        return True

    def reject(self):
        self.finish()
        Gui.Control.closeDialog()
        return True


class AddTube(_Command):
    name, menu = "AddTube", "Add drilling tube"
    tip = ("Add a guide sleeve: click its entry on the bone (direction: into the bone along the surface normal), "
           "set radii and length; added to the selected guide")

    def Activated(self):
        bones = [o for o in App.ActiveDocument.Objects if o.TypeId == "Mesh::Feature"]
        Gui.Control.showDialog(TubePanel(bones[0] if bones else None, (selected("Guide") or [None])[0]))


class TubePanel:
    last = None  # the open panel, for scripts and tests

    def __init__(self, bone, guide):
        TubePanel.last = self
        self.bone, self.guide = bone, guide
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Drilling tube")
        grid = QtGui.QFormLayout(self.form)
        self.fields = {}
        for key, label, value in (("inner", "Inner radius (mm)", preference("InnerRadius", 1.1)),
                                  ("outer", "Outer radius (mm)", preference("OuterRadius", 2.0)),
                                  ("length", "Length (mm)", preference("Length", 5.0)),
                                  ("offset", "Offset (mm)", preference("Offset", 3.0))):
            box = QtGui.QDoubleSpinBox()
            box.setRange(0.0, 100.0)
            box.setDecimals(2)
            box.setValue(value)
            grid.addRow(label, box)
            self.fields[key] = box
        self.entry = QtGui.QLabel("click the entry point on the bone")
        grid.addRow("Entry", self.entry)
        self.picked = None
        self.view = Gui.ActiveDocument.ActiveView
        self.callback = self.view.addEventCallback("SoMouseButtonEvent", self.on_mouse)

    def on_mouse(self, info):
        if info.get("State") == "DOWN" and info.get("Button") == "BUTTON1":
            self.click(info["Position"])

    def click(self, position):
        hit = self.view.getObjectInfo(tuple(position))
        if not hit or self.bone is None or hit.get("Object") != self.bone.Name:
            return False
        p = App.Vector(hit["x"], hit["y"], hit["z"])
        facet = hit.get("Facet", hit.get("Component"))
        normal = None
        if isinstance(facet, int) or (isinstance(facet, str) and facet.startswith("Facet")):
            index = facet if isinstance(facet, int) else int(facet[5:]) - 1
            normal = self.bone.Mesh.Facets[index].Normal
        if normal is None:
            normal = self.view.getViewDirection() * -1
        self.picked = (p, normal * -1)
        self.entry.setText(f"{p.x:.2f}, {p.y:.2f}, {p.z:.2f}")
        return True

    def accept(self):
        f = {k: v.value() for k, v in self.fields.items()}  # before closing deletes the widgets
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        if self.picked is None:
            return True
        p, d = self.picked
        code = (f"tube = SurgicalTemplate.make_tube(({p.x:.4f}, {p.y:.4f}, {p.z:.4f}), ({d.x:.5f}, {d.y:.5f}, "
                f"{d.z:.5f}), {f['inner']}, {f['outer']}, {f['length']}, {f['offset']})\n")
        if self.guide is not None:
            code += f"{ref(self.guide)}.Tubes = {ref(self.guide)}.Tubes + [tube]\n"
        run("Add drilling tube", code + "App.ActiveDocument.recompute()")
        return True

    def reject(self):
        self.view.removeEventCallback("SoMouseButtonEvent", self.callback)
        Gui.Control.closeDialog()
        return True


COMMANDS = {
    "SurgicalTemplate_OpenCase": OpenCase(),
    "SurgicalTemplate_SaveCase": SaveCase(),
    "SurgicalTemplate_ImportBone": ImportBone(),
    "SurgicalTemplate_DrawBoundary": DrawBoundary(),
    "SurgicalTemplate_CreateTemplate": CreateTemplate(),
    "SurgicalTemplate_AddTube": AddTube(),
    "SurgicalTemplate_CreateGuide": CreateGuide(),
    "SurgicalTemplate_Validate": Validate(),
    "SurgicalTemplate_ExportSTL": ExportSTL(),
}


def register():
    for name, command in COMMANDS.items():
        Gui.addCommand(name, command)
    return list(COMMANDS)

"""Surgical Template: the Python API, for macros and headless use (freecadcmd or Python with FreeCAD).

    import SurgicalTemplate as st
    guide = st.load_case("examples/cases/maxilla-implants.json")   # the whole parametric tree
    guide.Tubes[0].OuterRadius = 2.5                                   # any parameter, then
    guide.Document.recompute()
    st.export(guide, "guide.stl")

or step by step: make_bone, make_boundary, make_template, make_tube, make_guide (alias make_final).
Each call is one undo step. Lengths are in mm. Kernel failures raise ValueError (bad input) or
RuntimeError (geometry), naming what and where.
"""
import json
import os

import FreeCAD as App

import st_bridge
import st_features

__all__ = ["make_bone", "make_boundary", "make_template", "make_tube", "make_guide", "make_final", "export",
           "load_case", "save_case"]


def _doc(doc):
    return doc or App.ActiveDocument or App.newDocument("SurgicalTemplate")


class _Step:
    """One undo step around a change of the document."""

    def __init__(self, doc, title):
        self.doc, self.title = doc, title

    def __enter__(self):
        self.doc.openTransaction(self.title)
        return self

    def __exit__(self, kind, value, tb):
        if kind is None:
            self.doc.commitTransaction()
        else:
            self.doc.abortTransaction()
        return False


def _view(obj, icon):
    if App.GuiUp:
        st_features.ViewProvider(obj.ViewObject, icon)


def _vectors(points):
    return [App.Vector(*map(float, p)) for p in points]


def make_bone(source, doc=None, name="Bone"):
    """The bone: a Mesh feature from a mesh file (STL/PLY/OBJ, also .gz) or a Mesh.Mesh."""
    doc = _doc(doc)
    with _Step(doc, "Import bone"):
        obj = doc.addObject("Mesh::Feature", name)
        if isinstance(source, str):
            obj.Mesh = st_bridge.arrays_to_mesh(*st_bridge.read_mesh_file(source))
            obj.addProperty("App::PropertyFile", "SourceFile", "Bone", "The mesh file the bone was read from")
            obj.SourceFile = os.path.abspath(source)
            obj.Label = os.path.basename(source).split(".")[0]
        else:
            obj.Mesh = source
    if App.GuiUp:
        obj.ViewObject.ShapeColor = (0.93, 0.89, 0.80)
    return obj


def make_boundary(bone, points, inside=None, name="Boundary"):
    """A closed boundary curve on `bone` through control points (mm), optionally with a point inside
    the region to keep."""
    doc = bone.Document
    with _Step(doc, "Create boundary"):
        obj = doc.addObject("Part::FeaturePython", name)
        st_features.Boundary(obj)
        obj.Bone = bone
        obj.Points = _vectors(points)
        if inside is not None:
            obj.Inside = App.Vector(*map(float, inside))
            obj.UseInside = True
        _view(obj, "SurgicalTemplate_Boundary.svg")
    return obj


def make_template(boundary, thickness=2.5, clearance=0.0, resolution=0.0, sampling_step=0, name="Template"):
    """The template shell of a boundary."""
    doc = boundary.Document
    with _Step(doc, "Create template"):
        obj = doc.addObject("Mesh::FeaturePython", name)
        st_features.Template(obj)
        obj.Boundary = boundary
        obj.Thickness = thickness
        obj.Clearance = clearance
        obj.Resolution = resolution or 0.0
        obj.SamplingStep = int(sampling_step or 0)
        _view(obj, "SurgicalTemplate_Template.svg")
    return obj


def make_tube(entry, direction, inner_radius, outer_radius, length, offset=0.0, name="Tube", doc=None):
    """A drilling tube (guide sleeve) on a planned axis: entry at the bone, direction into it."""
    doc = _doc(doc)
    with _Step(doc, "Add drilling tube"):
        obj = doc.addObject("Part::FeaturePython", "Tube")
        st_features.Tube(obj)
        obj.Label = name
        obj.Entry = App.Vector(*map(float, entry))
        obj.Direction = App.Vector(*map(float, direction))
        obj.InnerRadius, obj.OuterRadius = inner_radius, outer_radius
        obj.Length, obj.Offset = length, offset
        _view(obj, "SurgicalTemplate_Tube.svg")
    return obj


def make_guide(shell, tubes=(), tolerance=0.01, name="SurgicalGuide"):
    """The final guide: the template shell with its tubes merged and their bores cut."""
    doc = shell.Document
    with _Step(doc, "Create surgical guide"):
        obj = doc.addObject("Mesh::FeaturePython", name)
        st_features.Guide(obj)
        obj.Shell = shell
        obj.Tubes = list(tubes)
        obj.Tolerance = tolerance
        _view(obj, "SurgicalTemplate_Guide.svg")
        if App.GuiUp:
            obj.ViewObject.ShapeColor = (0.20, 0.45, 0.85)
            # The guide replaces its shell and sleeves in the view (they stay in the tree under it).
            for part in [shell, *tubes]:
                part.ViewObject.Visibility = False
    return obj


make_final = make_guide


def export(obj, path):
    """Writes the mesh of a template or guide as binary STL (written whole or not at all)."""
    if not hasattr(obj, "Mesh"):
        raise ValueError(f"{obj.Label}: not a mesh object")
    if obj.Mesh.CountFacets == 0:
        raise ValueError(f"{obj.Label}: the mesh is empty (recompute it first)")
    st_bridge.kernel().write_stl(*st_bridge.mesh_to_arrays(obj.Mesh), path)
    return path


def load_case(path, doc=None):
    """Builds the whole parametric tree of a case file (docs/CASE-FORMAT.md) and returns the guide."""
    case = st_bridge.kernel().read_case(path)
    doc = doc or App.newDocument(case["name"].replace("-", "_") or "SurgicalTemplate")
    bone = make_bone(case["bone"], doc)
    boundary = make_boundary(bone, case["boundary_points"], case["inside"])
    shell = make_template(boundary, case["thickness"], case["clearance"], case["resolution"] or 0.0,
                          case["sampling_step"] or 0)
    tubes = [make_tube(t["entry"], t["direction"], t["inner_radius"], t["outer_radius"], t["length"], t["offset"],
                       name=t["name"], doc=doc) for t in case["tubes"]]
    guide = make_guide(shell, tubes)
    guide.Label = case["name"] or "SurgicalGuide"
    doc.recompute()
    return guide


def save_case(guide, path, output=None):
    """Writes the guide's plan as a case file, so that load_case(save_case(g)) rebuilds it."""
    shell = guide.Shell
    boundary = shell.Boundary
    bone = boundary.Bone
    source = getattr(bone, "SourceFile", "")
    if not source:
        raise ValueError(f"{bone.Label}: the bone was not read from a file; export it first")
    folder = os.path.dirname(os.path.abspath(path))
    case = {
        "format": st_bridge.kernel().CASE_FORMAT,
        "name": guide.Label,
        "bone": os.path.relpath(source, folder),
        "boundary": {"points": [st_bridge.vec(p) for p in boundary.Points]},
        "template": {"thickness": float(shell.Thickness.Value), "clearance": float(shell.Clearance.Value)},
        "tubes": [t.Proxy.spec(t) for t in guide.Tubes],
    }
    if boundary.UseInside:
        case["boundary"]["inside"] = st_bridge.vec(boundary.Inside)
    if shell.Resolution.Value > 0:
        case["template"]["resolution"] = float(shell.Resolution.Value)
    if shell.SamplingStep > 0:
        case["template"]["sampling_step"] = int(shell.SamplingStep)
    if output:
        case["output"] = output
    tmp = path + ".tmp"
    with open(tmp, "w") as f:
        json.dump(case, f, indent=2)
        f.write("\n")
    os.replace(tmp, path)
    return path

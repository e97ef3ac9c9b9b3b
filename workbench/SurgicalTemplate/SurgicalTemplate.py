"""Surgical Template: the Python API, for macros and headless use (freecadcmd or Python with FreeCAD).

    import SurgicalTemplate as st
    guide = st.load_case("examples/cases/maxilla-implants.json")   # the whole parametric tree
    guide.Tubes[0].OuterRadius = 2.5                                   # any parameter, then
    guide.Document.recompute()
    st.export(guide, "guide.stl")

or step by step: make_bone, make_boundary, make_template, make_tube, make_guide (alias make_final).
Plans from planning software: load_plan (3D Slicer markups, CSV of axes, case files); sleeve sizes:
sleeve_presets; documentation: make_drawing (TechDraw page, PDF, SVG, drill protocol). Each call is one
undo step. Lengths are in mm. Kernel failures raise ValueError (bad
input) or RuntimeError (geometry), naming what and where.
"""
import json
import os

import FreeCAD as App

import st_bridge
import st_features
from st_drawing import drill_protocol, make_drawing  # noqa: F401 (part of the API)

__all__ = ["make_bone", "make_boundary", "make_template", "make_tube", "make_guide", "make_final", "export",
           "load_case", "save_case", "load_plan", "sleeve_presets", "find_guide", "tree_of", "inspect", "thickness_colour", "make_drawing", "drill_protocol"]


def _doc(doc):
    return doc or App.ActiveDocument or App.newDocument("SurgicalTemplate")


class _Step:
    """One undo step around a change of the document; steps inside a step belong to the outer one.
    On failure the step is undone; where the document keeps no undo (UndoMode 0, as in freecadcmd)
    the objects it made are removed, so nothing half-made stays."""

    _open = set()  # documents with a step under way

    def __init__(self, doc, title):
        self.doc, self.title = doc, title
        self.outer = False

    def __enter__(self):
        if self.doc.Name not in _Step._open:
            _Step._open.add(self.doc.Name)
            self.outer = True
            self.before = {o.Name for o in self.doc.Objects}
            self.doc.openTransaction(self.title)
        return self

    def __exit__(self, kind, value, tb):
        if self.outer:
            _Step._open.discard(self.doc.Name)
            if kind is None:
                self.doc.commitTransaction()
            else:
                self.doc.abortTransaction()
                for name in [o.Name for o in self.doc.Objects if o.Name not in self.before][::-1]:
                    if self.doc.getObject(name) is not None:
                        self.doc.removeObject(name)
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
            obj.addProperty("App::PropertyEnumeration", "CoordinateSystem", "Bone",
                            "The bone's frame (3D Slicer: LPS unless the file's header says SPACE=RAS); plans "
                            "in the other frame are converted on import")
            obj.CoordinateSystem = ["LPS", "RAS"]
            obj.CoordinateSystem = st_bridge.kernel().mesh_file_space(source)
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


def make_tube(entry, direction, inner_radius=None, outer_radius=None, length=None, offset=None, name="Tube",
              doc=None, preset=None, depth=0.0, guide=None):
    """A drilling tube (guide sleeve) on a planned axis: entry at the bone, direction into it. Sizes
    not given come from `preset` (a name from sleeve_presets() or one of its dicts; the tube's Preset
    names it when its sizes are the preset's); depth is the planned drilling depth beyond the entry,
    for the drill protocol. With `guide`, the tube is added to it in the same undo step."""
    doc = guide.Document if guide is not None else _doc(doc)
    sizes = _preset(preset) if preset is not None else {}
    given = {"inner_radius": inner_radius, "outer_radius": outer_radius, "length": length, "offset": offset}
    for key, value in given.items():
        if value is None:
            if key == "offset" and not sizes:
                given[key] = 0.0
            elif key not in sizes:
                raise ValueError(f"{name}: no {key} given and no sleeve preset to take it from")
            else:
                given[key] = sizes[key]
    with _Step(doc, "Add drilling tube"):
        obj = doc.addObject("Part::FeaturePython", "Tube")
        st_features.Tube(obj)
        obj.Label = name
        obj.Entry = App.Vector(*map(float, entry))
        obj.Direction = App.Vector(*map(float, direction))
        obj.InnerRadius, obj.OuterRadius = given["inner_radius"], given["outer_radius"]
        obj.Length, obj.Offset = given["length"], given["offset"]
        obj.Depth = depth or 0.0
        if sizes.get("name") and all(abs(given[k] - sizes[k]) < 1e-9 for k in given):
            obj.Preset = sizes["name"]
        _view(obj, "SurgicalTemplate_Tube.svg")
        if guide is not None:
            guide.Tubes = guide.Tubes + [obj]
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
    with _Step(doc, "Open case"):
        bone = make_bone(case["bone"], doc)
        boundary = make_boundary(bone, case["boundary_points"], case["inside"])
        shell = make_template(boundary, case["thickness"], case["clearance"], case["resolution"] or 0.0,
                              case["sampling_step"] or 0)
        tubes = [make_tube(t["entry"], t["direction"], t["inner_radius"], t["outer_radius"], t["length"],
                           t["offset"], name=t["name"], doc=doc, depth=t["depth"]) for t in case["tubes"]]
        guide = make_guide(shell, tubes)
        guide.Label = case["name"] or "SurgicalGuide"
    doc.recompute()
    return guide


def thickness_colour(distance, thickness, clearance=0.0, tolerance=0.01):
    """The thickness map's colour (r, g, b in 0..1) of a distance from the bone (mm): red in the bone,
    green where the guide seats, through yellow to blue at the outer surface, grey beyond (sleeves)."""
    if distance < -tolerance:
        return (0.85, 0.15, 0.12)
    top = clearance + thickness
    if distance > top * 1.25:
        return (0.62, 0.64, 0.68)
    t = min(max((distance - clearance) / max(thickness, 1e-9), 0.0), 1.0)
    stops = ((0.0, (0.16, 0.70, 0.28)), (0.5, (0.95, 0.80, 0.15)), (1.0, (0.20, 0.45, 0.85)))
    for (t0, c0), (t1, c1) in zip(stops, stops[1:]):
        if t <= t1:
            u = (t - t0) / (t1 - t0)
            return tuple(a + (b - a) * u for a, b in zip(c0, c1))
    return stops[-1][1]


def inspect(obj, show=True, tolerance=0.01):
    """Inspects a guide or template on its bone with the kernel: {passed, summary, solid, vertices_in_bone,
    deepest_in_bone, seated_vertices, bores: [{name, margin, open}], face_distance (per facet, mm from
    the bone, negative inside it), thickness, clearance}. With `show` in the GUI, the facets are coloured
    by thickness_colour (the thickness map; recomputing the object removes it)."""
    kind = _kind(obj)
    if kind not in ("Guide", "Template"):
        raise ValueError(f"{obj.Label}: only a guide or a template can be inspected")
    shell = obj.Shell if kind == "Guide" else obj
    if shell is None or shell.Boundary is None or shell.Boundary.Bone is None:
        raise ValueError(f"{obj.Label}: not on a bone")
    if obj.Mesh.CountFacets == 0:
        raise ValueError(f"{obj.Label}: the mesh is empty (recompute it first)")
    k = st_bridge.kernel()
    V, F = st_bridge.mesh_to_arrays(obj.Mesh)
    tubes = [t.Proxy.spec(t) for t in obj.Tubes] if kind == "Guide" else []
    clearance, thickness = float(shell.Clearance.Value), float(shell.Thickness.Value)
    r = st_bridge.call(k.inspect_guide, V, F, *st_bridge.bone_arrays(shell.Boundary.Bone), tubes, clearance,
                       tolerance)
    d = r.pop("vertex_distance")
    r["face_distance"] = [float(x) for x in d[F].mean(axis=1)]  # FreeCAD keeps the facet order
    r["thickness"], r["clearance"] = thickness, clearance
    if show and App.GuiUp:
        if "ThicknessMap" not in obj.PropertiesList:
            # An output that touches nothing: showing the map does not make the guide recompute.
            obj.addProperty("App::PropertyColorList", "ThicknessMap", "Validation",
                            "Facet colours of the last inspection (distance from the bone)", 8 | 16)
            obj.setEditorMode("ThicknessMap", 2)
        obj.ThicknessMap = [thickness_colour(x, thickness, clearance, tolerance) for x in r["face_distance"]]
        obj.ViewObject.Coloring = True
    return r


def _kind(obj):
    return getattr(getattr(obj, "Proxy", None), "kind", "Bone" if getattr(obj, "TypeId", "") == "Mesh::Feature" else "")


def tree_of(obj):
    """(guide, template, boundary, bone) built on `obj` (any of them), the latest of each where a bone
    or boundary carries several; None for what does not exist yet."""
    kind = _kind(obj)
    guide = obj if kind == "Guide" else None
    shell = obj if kind == "Template" else guide.Shell if guide else None
    boundary = obj if kind == "Boundary" else shell.Boundary if shell else None
    bone = obj if kind == "Bone" else boundary.Bone if boundary else None
    objects = obj.Document.Objects
    if boundary is None:
        boundaries = [o for o in objects if _kind(o) == "Boundary" and o.Bone == bone]
        boundary = boundaries[-1] if boundaries else None
    if shell is None and boundary is not None:
        shells = [o for o in objects if _kind(o) == "Template" and o.Boundary == boundary]
        shell = shells[-1] if shells else None
    if guide is None and shell is not None:
        guides = [o for o in objects if _kind(o) == "Guide" and o.Shell == shell]
        guide = guides[-1] if guides else None
    return guide, shell, boundary, bone


def find_guide(obj):
    """The guide built on `obj` (a guide, template, boundary or bone), or None."""
    return tree_of(obj)[0] if obj is not None else None


def sleeve_presets():
    """The sleeve catalogue: the project's (data/sleeve-presets.json) and the user's own file
    <FreeCAD user data>/SurgicalTemplate/sleeve-presets.json, whose sleeves add to it or replace
    those of the same name. Each: {name, description, inner_radius, outer_radius, length, offset} (mm)."""
    k = st_bridge.kernel()
    presets = {p["name"]: p for p in k.sleeve_presets()}
    mine = user_presets_path()
    if os.path.exists(mine):
        presets.update({p["name"]: p for p in k.sleeve_presets(mine)})
    return list(presets.values())


def user_presets_path():
    return os.path.join(App.getUserAppDataDir(), "SurgicalTemplate", "sleeve-presets.json")


def _preset(preset):
    if isinstance(preset, dict):
        return preset
    presets = sleeve_presets()
    for p in presets:
        if p["name"] == preset or p["name"].lower() == str(preset).lower():
            return p
    raise ValueError(f"no sleeve preset {preset!r}; the catalogue has " + ", ".join(p["name"] for p in presets))


def load_plan(path, target=None, preset=None, thickness=None):
    """Imports a plan into the document: a case file builds its whole tree (as load_case); a 3D Slicer
    markups file (.mrk.json) or a CSV of axes goes onto `target` (a guide, template, boundary or bone;
    default: the active document's guide or bone), converted into the bone's CoordinateSystem. The
    plan's boundary replaces the boundary's points (or, on a bare bone, makes a boundary and a
    template of `thickness`); its axes become tubes added to the guide (made when missing), with sizes
    the plan lacks from `preset`. One undo step; returns the guide (or the boundary when there are no
    axes and no template)."""
    k = st_bridge.kernel()
    doc = target.Document if target is not None else App.ActiveDocument
    if target is None and doc is not None:
        guides = [o for o in doc.Objects if _kind(o) == "Guide"]
        bones = [o for o in doc.Objects if _kind(o) == "Bone"]
        target = guides[0] if guides else bones[0] if bones else None
    guide = shell = boundary = bone = None
    if target is not None:
        kind = _kind(target)
        if kind not in ("Guide", "Template", "Boundary", "Bone"):
            raise ValueError(f"{target.Label}: a plan goes on a guide, template, boundary or bone, "
                             f"not a {kind or target.TypeId}")
        guide, shell, boundary, bone = tree_of(target)
    plan = k.read_plan(path, getattr(bone, "CoordinateSystem", "LPS"))
    if plan["kind"] == "case":
        return load_case(path)
    if bone is None:
        raise ValueError(f"{path}: a markups or CSV plan needs a bone to go on"
                         + (f"; the document {doc.Label} has none" if doc is not None else ""))
    for w in plan["warnings"]:
        App.Console.PrintWarning(f"Surgical Template: {w}\n")
    sizes = _preset(preset) if preset is not None else None
    tubes = [k.tube_from_axis(a, sizes) for a in plan["axes"]]  # every size checked before any change
    if tubes and boundary is None and plan["boundary_points"] is None:
        raise ValueError(f"{path}: the plan has drilling axes but {bone.Label} has no boundary to put the "
                         "template on; import or draw a boundary first")
    with _Step(doc, "Import plan"):
        if plan["boundary_points"] is not None:
            if boundary is None:
                boundary = make_boundary(bone, plan["boundary_points"], plan["inside"])
            else:
                boundary.Points = _vectors(plan["boundary_points"])
                if plan["inside"] is not None:
                    boundary.Inside, boundary.UseInside = App.Vector(*map(float, plan["inside"])), True
                elif boundary.UseInside:
                    App.Console.PrintWarning(f"Surgical Template: {path}: a new boundary without an inside point: "
                                             f"{boundary.Label}'s inside point is dropped (the smaller region is kept)\n")
                    boundary.UseInside = False
        if shell is None and (plan["boundary_points"] is not None or tubes):
            shell = make_template(boundary, thickness or 2.5)
        new = [make_tube(t["entry"], t["direction"], t["inner_radius"], t["outer_radius"], t["length"], t["offset"],
                         name=t["name"], doc=doc, depth=t["depth"], preset=sizes) for t in tubes]
        if new:
            if guide is None:
                guide = make_guide(shell, new)
            else:
                guide.Tubes = guide.Tubes + new
    doc.recompute()
    return guide or shell or boundary


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

"""Making the parametric tree step by step: the bone, a boundary on it, the template shell, drilling
tubes and the guide. Each call is one undo step; lengths in mm. View providers are attached when
FreeCAD's GUI is up."""
import os

import FreeCAD as App

import st_bridge
from stfunctions import presets
from stmake.step import Step, document
from stobjects.boundary import Boundary
from stobjects.guide import Guide
from stobjects.parts import CLOSED, Label, Slot, outward_normal
from stobjects.template import Template
from stobjects.tube import Tube
from stviewproviders.view_feature import GUIDE_COLOUR, ViewProvider


def view_of(obj, icon):
    if App.GuiUp:
        ViewProvider(obj.ViewObject, icon)


def vectors(points):
    return [App.Vector(*map(float, p)) for p in points]


def make_bone(source, doc=None, name="Bone"):
    """The bone: a Mesh feature from a mesh file (STL/PLY/OBJ, also .gz) or a Mesh.Mesh."""
    doc = document(doc)
    with Step(doc, "Import bone"):
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
    with Step(doc, "Create boundary"):
        obj = doc.addObject("Part::FeaturePython", name)
        Boundary(obj)
        obj.Bone = bone
        obj.Points = vectors(points)
        if inside is not None:
            obj.Inside = App.Vector(*map(float, inside))
            obj.UseInside = True
        view_of(obj, "SurgicalTemplate_Boundary.svg")
    return obj


def make_template(boundary, thickness=2.5, clearance=0.0, resolution=0.0, sampling_step=0, name="Template",
                  insertion="auto"):
    """The template shell of a boundary. insertion: "auto" (the least-undercut direction, the default
    for new templates), a direction, or None (no insertion analysis)."""
    doc = boundary.Document
    with Step(doc, "Create template"):
        obj = doc.addObject("Mesh::FeaturePython", name)
        Template(obj)
        obj.Boundary = boundary
        obj.Thickness = thickness
        obj.Clearance = clearance
        obj.Resolution = resolution or 0.0
        obj.SamplingStep = int(sampling_step or 0)
        set_insertion(obj, insertion)
        view_of(obj, "SurgicalTemplate_Template.svg")
    return obj


_RADII = {"InnerRadius": "InnerDiameter", "OuterRadius": "OuterDiameter", "CounterboreRadius": "CounterboreDiameter"}


def edit(obj, **values):
    """Changes a workbench object's properties by name and recomputes: one undo step. Lengths in mm,
    vectors as 3 numbers; a text starting with "=" binds the property to that expression (as typed in
    FreeCAD's property editor: "=Spreadsheet.D"), None removes a property's expression. Returns the
    object."""
    unknown = [k for k in values if k not in obj.PropertiesList]
    if unknown:
        raise ValueError(f"{obj.Label}: no property {', '.join(unknown)}")
    with Step(obj.Document, f"Edit {obj.Label}"):
        for name, value in values.items():
            if value is None:
                obj.setExpression(name, None)
            elif isinstance(value, str) and value.startswith("="):
                obj.setExpression(name, value[1:])
            else:
                setattr(obj, name, App.Vector(*value) if isinstance(value, (tuple, list)) else value)
    obj.Document.recompute()
    return obj


def edit_tube(tube, **values):
    """edit() for a tube (InnerDiameter, OuterDiameter, Length, Offset, Entry, Direction, Depth, ...). The
    radii of macros written before 0.4 (InnerRadius, OuterRadius, CounterboreRadius) set the diameters."""
    for old, new in _RADII.items():
        if old in values and old not in tube.PropertiesList:
            values[new] = 2.0 * float(values.pop(old))
    return edit(tube, **values)


def set_insertion(template, direction):
    """Sets a template's insertion: "auto", a direction (the guide moves along it onto the bone; e.g. the
    3D view's direction), or None (no block-out, no removal check). One undo step; recompute after."""
    with Step(template.Document, "Set insertion direction"):
        if direction is None:
            template.Insertion = "None"
        elif isinstance(direction, str):
            if direction != "auto":
                raise ValueError(f'insertion: "auto", a direction or None, not "{direction}"')
            template.Insertion = "Auto"
        else:
            d = App.Vector(*[float(c) for c in direction])
            if d.Length == 0:
                raise ValueError("insertion: the direction must not be zero")
            template.Insertion = "Direction"
            template.InsertionDirection = d.normalize()
    return template


def make_tube(entry, direction, inner_radius=None, outer_radius=None, length=None, offset=None, name="Tube",
              doc=None, preset=None, depth=0.0, guide=None, kind=None, counterbore=None, inner_diameter=None,
              outer_diameter=None):
    """A drilling tube (guide sleeve) on a planned axis: entry at the bone, direction into it. Sizes
    not given come from `preset` (a name from sleeve_presets() or one of its dicts; the tube's Preset
    names it when its sizes are the preset's); depth is the planned drilling depth beyond the entry,
    for the drill protocol. kind "pin" makes a fixation pin's tube; counterbore {"radius", "depth"} a
    hole for a screw's head (both from the preset when not given). With `guide`, the tube is added to
    it in the same undo step. Sizes by radius as in case files, or by diameter (inner_diameter,
    outer_diameter) as the Tube's properties and the catalogues give them."""
    for radius, diameter, what in ((inner_radius, inner_diameter, "inner"), (outer_radius, outer_diameter, "outer")):
        if radius is not None and diameter is not None:
            raise ValueError(f"{name}: give the {what} radius or the {what} diameter, not both")
    inner_radius = inner_diameter / 2.0 if inner_diameter is not None else inner_radius
    outer_radius = outer_diameter / 2.0 if outer_diameter is not None else outer_radius
    doc = guide.Document if guide is not None else document(doc)
    sizes = presets.preset(preset) if preset is not None else {}
    given = {"inner_radius": inner_radius, "outer_radius": outer_radius, "length": length, "offset": offset}
    for key, value in given.items():
        if value is None:
            if key == "offset" and not sizes:
                given[key] = 0.0
            elif key not in sizes:
                raise ValueError(f"{name}: no {key} given and no sleeve preset to take it from")
            else:
                given[key] = sizes[key]
    with Step(doc, "Add drilling tube"):
        obj = doc.addObject("Part::FeaturePython", "Tube")
        Tube(obj)
        obj.Label = name
        obj.Entry = App.Vector(*map(float, entry))
        obj.Direction = App.Vector(*map(float, direction))
        obj.InnerDiameter, obj.OuterDiameter = 2.0 * given["inner_radius"], 2.0 * given["outer_radius"]
        obj.Length, obj.Offset = given["length"], given["offset"]
        obj.Depth = depth or 0.0
        obj.Kind = kind or sizes.get("kind") or "sleeve"
        counterbore = counterbore or sizes.get("counterbore")
        if counterbore:
            obj.CounterboreDiameter, obj.CounterboreDepth = 2.0 * counterbore["radius"], counterbore["depth"]
        if sizes.get("name") and all(abs(given[k] - sizes[k]) < 1e-9 for k in given):
            obj.Preset = sizes["name"]
        view_of(obj, "SurgicalTemplate_Tube.svg")
        if guide is not None:
            guide.Tubes = guide.Tubes + [obj]
    return obj


def make_guide(shell, tubes=(), tolerance=0.01, name="SurgicalGuide", slots=(), labels=()):
    """The final guide: the template shell with its tubes merged and their bores cut, its saw slots
    (dicts with the case file's slot keys) cut in their housings and its labels (dicts with the case
    file's label keys) engraved or embossed."""
    doc = shell.Document
    with Step(doc, "Create surgical guide"):
        obj = doc.addObject("Mesh::FeaturePython", name)
        Guide(obj)
        obj.Shell = shell
        obj.Tubes = list(tubes)
        obj.Tolerance = tolerance
        view_of(obj, "SurgicalTemplate_Guide.svg")
        for item in slots:
            make_slot(obj, item)
        for item in labels:
            make_label(obj, item)
        # The guide replaces its shell and sleeves in the view (they stay in the tree under it); the
        # document's own Visibility, so that a document made without the GUI opens the same way.
        for part in [shell, *tubes]:
            part.Visibility = False
        if App.GuiUp:
            obj.ViewObject.ShapeColor = GUIDE_COLOUR
    return obj


make_final = make_guide


def make_slot(guide, item):
    """A Slot object from a slot dict (the case file's keys), added to the guide's Parts (no recompute)."""
    doc = guide.Document
    obj = doc.addObject("Part::FeaturePython", "Slot")
    Slot(obj)
    obj.Label = item["name"]
    obj.Origin = App.Vector(*map(float, item["origin"]))
    obj.Normal = App.Vector(*map(float, item["normal"]))
    obj.Travel = App.Vector(*map(float, item["direction"])) if item.get("direction") is not None else App.Vector()
    obj.Blade = float(item["blade"])
    for key, prop in (("clearance", "Clearance"), ("length", "Length"), ("height", "Height"), ("wall", "Wall")):
        if item.get(key) is not None:
            setattr(obj, prop, float(item[key]))
    closed = sorted(item.get("closed", ["start", "end"]))
    obj.Closed = [k for k, v in CLOSED.items() if sorted(v) == closed][0]
    blades = presets.blade_presets()
    Slot.set_blades(obj, blades)
    same = [b["name"] for b in blades if abs(b["thickness"] - obj.Blade.Value) < 1e-9
            and abs(b["clearance"] - obj.Clearance.Value) < 1e-9]
    obj.BladePreset = same[0] if same else "custom"
    _attach(guide, obj, "SurgicalTemplate_Slot.svg")
    return obj


def make_label(guide, item):
    """A Label object from a label dict (the case file's keys), added to the guide's Parts (no recompute);
    it faces out of the bone at its place."""
    doc = guide.Document
    obj = doc.addObject("Part::FeaturePython", "Label")
    Label(obj)
    obj.Label = item.get("name") or f"label {len(Guide.labels_of(guide)) + 1}"
    obj.Text = item["text"]
    obj.At = App.Vector(*map(float, item["at"]))
    obj.Up = App.Vector(*map(float, item["up"]))
    for key, prop in (("height", "Height"), ("depth", "Depth")):
        if item.get(key) is not None:
            setattr(obj, prop, float(item[key]))
    obj.Mode = item.get("mode", "engrave")
    shell = guide.Shell
    bone = shell.Boundary.Bone if shell is not None and shell.Boundary is not None else None
    if bone is not None:
        obj.Facing = outward_normal(bone, item["at"])
    _attach(guide, obj, "SurgicalTemplate_Label.svg")
    return obj


def _attach(guide, obj, icon):
    guide.Parts = list(guide.Parts) + [obj]
    obj.Visibility = False   # the guide shows it built; the object stays in the tree under the guide
    view_of(obj, icon)

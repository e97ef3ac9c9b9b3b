"""Plans from planning software onto the document: 3D Slicer markups, CSV of axes or planes, case files."""
import FreeCAD as App

import st_bridge
from stfunctions import presets
from stfunctions.query import tree_of
from stmake.case import load_case
from stmake.objects import make_boundary, make_guide, make_template, make_tube, vectors
from stmake.parts import make_slot
from stmake.step import Step
from stobjects.base import kind_of
from stobjects.guide import Guide


def load_plan(path, target=None, preset=None, thickness=None, blade=None, slot_length=None):
    """Imports a plan into the document: a case file builds its whole tree (as load_case); a 3D Slicer
    markups file (.mrk.json) or a CSV of axes or planes goes onto `target` (a guide, template, boundary
    or bone; default: the active document's guide or bone), converted into the bone's CoordinateSystem.
    The plan's boundary replaces the boundary's points (or, on a bare bone, makes a boundary and a
    template of `thickness`); its axes become tubes added to the guide (made when missing), with sizes
    the plan lacks from `preset`; its cut planes become saw slots added to the guide, with the blade
    (a catalogue name, a thickness in mm or a blade dict) and `slot_length` (mm) the plan lacks, the
    saw travelling into the bone in each plane. One undo step; returns the guide (or the boundary when
    there are no axes, no planes and no template)."""
    k = st_bridge.kernel()
    doc = target.Document if target is not None else App.ActiveDocument
    if target is None and doc is not None:
        guides = [o for o in doc.Objects if kind_of(o) == "Guide"]
        bones = [o for o in doc.Objects if kind_of(o) == "Bone"]
        target = guides[0] if guides else bones[0] if bones else None
    guide = shell = boundary = bone = None
    if target is not None:
        kind = kind_of(target)
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
    sizes = presets.preset(preset) if preset is not None else None
    # The kernel's apply_plan on the case of what is there (boundary, inside point): every size is
    # checked before any change; the plan's axes come back as tubes to add.
    case = {"boundary_points": [st_bridge.vec(p) for p in boundary.Points] if boundary is not None else None,
            "inside": st_bridge.vec(boundary.Inside) if boundary is not None and boundary.UseInside else None}
    blade_sizes = presets.blade(blade) if blade is not None else None
    new, warnings = k.apply_plan(case, path, getattr(bone, "CoordinateSystem", "LPS"), sizes, add_tubes=True,
                                 blade=blade_sizes, slot_length=slot_length)
    for w in warnings:
        App.Console.PrintWarning(f"Surgical Template: {w}\n")
    tubes, slots = new["tubes"], new["slots"]
    if (tubes or slots) and boundary is None and plan["boundary_points"] is None:
        raise ValueError(f"{path}: the plan has drilling axes or cut planes but {bone.Label} has no boundary to "
                         "put the template on; import or draw a boundary first")
    if slots and guide is not None:
        taken = {s.get("name") for s in Guide.slots_of(guide)}
        for s in slots:
            if s["name"] in taken:
                raise ValueError(f"{path}: plane \"{s['name']}\": {guide.Label} has a slot of that name already")
    with Step(doc, "Import plan"):
        if plan["boundary_points"] is not None:
            if boundary is None:
                boundary = make_boundary(bone, plan["boundary_points"], plan["inside"])
            else:
                boundary.Points = vectors(new["boundary_points"])
                if new["inside"] is not None:
                    boundary.Inside, boundary.UseInside = App.Vector(*map(float, new["inside"])), True
                else:
                    boundary.UseInside = False
        if shell is None and (plan["boundary_points"] is not None or tubes):
            shell = make_template(boundary, thickness or 2.5)
        added = [make_tube(t["entry"], t["direction"], t["inner_radius"], t["outer_radius"], t["length"],
                           t["offset"], name=t["name"], doc=doc, depth=t["depth"], preset=sizes) for t in tubes]
        if added or slots:
            if guide is None:
                guide = make_guide(shell, added, slots=slots)
            else:
                guide.Tubes = guide.Tubes + added
                for s in slots:
                    make_slot(guide, s)
    doc.recompute()
    return guide or shell or boundary

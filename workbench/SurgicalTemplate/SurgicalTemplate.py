"""Surgical Template: the Python API, for macros and headless use (freecadcmd or Python with FreeCAD).

    import SurgicalTemplate as st
    guide = st.load_case("examples/cases/maxilla-implants.json")   # the whole parametric tree
    guide.Tubes[0].OuterDiameter = 5.0                                 # any parameter, then
    guide.Document.recompute()
    st.export(guide, "guide.stl")

or step by step: make_bone, make_boundary, make_template, make_tube, make_guide (alias make_final); a
cutting guide's saw slots and labels: add_slot, add_label.
Plans from planning software: load_plan (3D Slicer markups, CSV of axes or cut planes, case files);
sleeve sizes and saw blades: sleeve_presets, blade_presets; documentation: make_drawing (TechDraw page,
PDF, SVG, drill protocol) with its title block from set_case_info (owner, status, revision, case id, ...). Each call is one undo step. Lengths are in mm. Kernel failures raise
ValueError (bad input) or RuntimeError (geometry), naming what and where.

This module is the API's face: the functions live in stmake (making and changing objects),
stfunctions (finding, inspecting, the sleeve catalogue) and stdrawing (the documentation drawing); the
objects in stobjects, their view providers in stviewproviders, the GUI in stcommands and sttaskpanels.
"""
import st_bridge  # noqa: F401  (scripts reach the kernel as SurgicalTemplate.st_bridge)
from stdrawing.protocol import drill_protocol
from stfunctions.inspection import inspect, thickness_colour
from stfunctions.presets import blade_presets, sleeve_presets, user_presets_path
from stfunctions.query import find_guide, tree_of
from stmake.case import load_case, save_case, set_case_info
from stmake.drawing import make_drawing
from stmake.export import export
from stmake.objects import (edit, edit_tube, make_bone, make_boundary, make_final, make_guide, make_template, make_tube,
                            set_insertion)
from stmake.parts import add_label, add_slot
from stmake.plan import load_plan
from stmake.step import Step as _Step  # noqa: F401  (scripts and tests group their changes in one undo step)
from stobjects.guide import Guide as _Guide

slots_of = _Guide.slots_of     # a guide's saw slots as the case file's keys (its Slot objects)
labels_of = _Guide.labels_of   # a guide's labels as the case file's keys (its Label objects)

__all__ = ["make_bone", "make_boundary", "make_template", "make_tube", "make_guide", "make_final", "export",
           "load_case", "save_case", "load_plan", "sleeve_presets", "blade_presets", "find_guide", "tree_of", "inspect", "thickness_colour", "make_drawing", "drill_protocol",
           "add_label", "add_slot", "edit", "edit_tube", "set_case_info", "slots_of", "labels_of"]

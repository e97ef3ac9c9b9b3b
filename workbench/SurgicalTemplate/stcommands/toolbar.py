"""The workbench's commands in toolbar and menu order (three groups: the case, the design, checks and
output), their shortcuts, the context menu for what is selected, and their registration with FreeCAD."""
import FreeCADGui as Gui

from stcommands.design import (AddLabel, AddSlot, AddTube, CreateGuide, CreateTemplate, DrawBoundary,
                               InsertionFromView, Validate)
from stcommands.files import (ExampleCase, ExportSTL, ImportBone, ImportPlan, MakeDrawing, OpenCase, OpenExample,
                              SaveCase, example_cases)


COMMANDS = {
    "SurgicalTemplate_OpenCase": OpenCase(),
    "SurgicalTemplate_OpenExample": OpenExample(),
    "SurgicalTemplate_ImportPlan": ImportPlan(),
    "SurgicalTemplate_SaveCase": SaveCase(),
    "SurgicalTemplate_ImportBone": ImportBone(),
    "SurgicalTemplate_DrawBoundary": DrawBoundary(),
    "SurgicalTemplate_CreateTemplate": CreateTemplate(),
    "SurgicalTemplate_InsertionFromView": InsertionFromView(),
    "SurgicalTemplate_AddTube": AddTube(),
    "SurgicalTemplate_CreateGuide": CreateGuide(),
    "SurgicalTemplate_AddSlot": AddSlot(),
    "SurgicalTemplate_AddLabel": AddLabel(),
    "SurgicalTemplate_Validate": Validate(),
    "SurgicalTemplate_ExportSTL": ExportSTL(),
    "SurgicalTemplate_Drawing": MakeDrawing(),
}


GROUPS = (
    ("Case", ["SurgicalTemplate_OpenCase", "SurgicalTemplate_OpenExample", "SurgicalTemplate_ImportBone", "SurgicalTemplate_ImportPlan",
              "SurgicalTemplate_SaveCase"]),
    ("Design", ["SurgicalTemplate_DrawBoundary", "SurgicalTemplate_CreateTemplate",
                "SurgicalTemplate_InsertionFromView", "SurgicalTemplate_AddTube", "SurgicalTemplate_CreateGuide",
                "SurgicalTemplate_AddSlot", "SurgicalTemplate_AddLabel"]),
    ("Check and output", ["SurgicalTemplate_Validate", "SurgicalTemplate_ExportSTL", "SurgicalTemplate_Drawing"]),
)

# Two-key shortcuts, as FreeCAD's workbenches have them ("T" for template), for the frequent commands.
SHORTCUTS = {
    "SurgicalTemplate_OpenCase": "T, O",
    "SurgicalTemplate_DrawBoundary": "T, B",
    "SurgicalTemplate_CreateTemplate": "T, M",
    "SurgicalTemplate_AddTube": "T, T",
    "SurgicalTemplate_CreateGuide": "T, G",
    "SurgicalTemplate_Validate": "T, V",
    "SurgicalTemplate_ExportSTL": "T, E",
}

# What the context menu offers on a selected object of each kind.
CONTEXT = {
    "Bone": ["SurgicalTemplate_DrawBoundary", "SurgicalTemplate_ImportPlan"],
    "Boundary": ["SurgicalTemplate_CreateTemplate"],
    "Template": ["SurgicalTemplate_InsertionFromView", "SurgicalTemplate_AddTube", "SurgicalTemplate_CreateGuide",
                 "SurgicalTemplate_Validate", "SurgicalTemplate_ExportSTL"],
    "Guide": ["SurgicalTemplate_AddTube", "SurgicalTemplate_AddSlot", "SurgicalTemplate_AddLabel",
              "SurgicalTemplate_ImportPlan", "Separator", "SurgicalTemplate_Validate", "SurgicalTemplate_ExportSTL",
              "SurgicalTemplate_Drawing", "SurgicalTemplate_SaveCase"],
}


def register():
    """Registers the commands with their shortcuts; returns (toolbars, menu): a toolbar per group, and the
    menu's commands with separators between the groups."""
    for name, path in example_cases().items():   # the "Open example" submenu's entries
        Gui.addCommand(name, ExampleCase(path))
    for name, command in COMMANDS.items():
        command.accel = SHORTCUTS.get(name, "")
        Gui.addCommand(name, command)
    menu = []
    for _, names in GROUPS:
        menu += (["Separator"] if menu else []) + names
    return [(f"Surgical Template {title.lower()}", names) for title, names in GROUPS], menu


def context_menu(selection):
    """The commands the context menu offers for the selected objects (their kinds' lists, once each)."""
    from stobjects.base import kind_of
    out = []
    for obj in selection:
        for name in CONTEXT.get(kind_of(obj), []):
            if name == "Separator" or name not in out:
                out.append(name)
    while out and out[-1] == "Separator":
        out.pop()
    return out

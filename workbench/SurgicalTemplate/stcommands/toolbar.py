"""The workbench's commands in toolbar and menu order, and their registration with FreeCAD."""
import FreeCADGui as Gui

from stcommands.design import (AddLabel, AddSlot, AddTube, CreateGuide, CreateTemplate, DrawBoundary,
                               InsertionFromView, Validate)
from stcommands.files import ExportSTL, ImportBone, ImportPlan, MakeDrawing, OpenCase, SaveCase


COMMANDS = {
    "SurgicalTemplate_OpenCase": OpenCase(),
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


def register():
    for name, command in COMMANDS.items():
        Gui.addCommand(name, command)
    return list(COMMANDS)

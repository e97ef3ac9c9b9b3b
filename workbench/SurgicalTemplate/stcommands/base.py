"""The base of the workbench's commands: icon, menu text and tool tip, active with a document."""
import FreeCAD as App

from stutils.gui_utils import icon


class Command:
    """A FreeCAD command; subclasses name it and define Activated (and IsActive where needed)."""

    name = ""
    menu = ""
    tip = ""
    needs_document = True

    def GetResources(self):
        return {"Pixmap": icon(self.name), "MenuText": self.menu, "ToolTip": self.tip}

    def IsActive(self):
        return App.ActiveDocument is not None or not self.needs_document

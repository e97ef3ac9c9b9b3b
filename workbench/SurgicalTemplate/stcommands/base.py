"""The base of the workbench's commands: icon, menu text and tool tip, active with a document."""
import FreeCAD as App

from stutils.gui_utils import icon


class Command:
    """A FreeCAD command; subclasses name it and define Activated (and IsActive where needed)."""

    name = ""
    menu = ""
    tip = ""
    pixmap = ""  # its icon's name when not its own (SurgicalTemplate_<name>.svg)
    accel = ""  # its shortcut (stcommands.toolbar.SHORTCUTS)
    needs_document = True

    def GetResources(self):
        resources = {"Pixmap": icon(self.pixmap or self.name), "MenuText": self.menu, "ToolTip": self.tip}
        if self.accel:
            resources["Accel"] = self.accel
        return resources

    def IsActive(self):
        return App.ActiveDocument is not None or not self.needs_document

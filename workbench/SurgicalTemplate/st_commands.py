"""Alias module for scripts: the GUI commands' functions and task panels as scripts and tests reach them
(st_commands.open_case, .import_bone, .import_plan, BoundaryPanel.last, ...). Their homes are now
stcommands and sttaskpanels."""
from stcommands.files import ask_preset, import_bone, import_plan, open_case  # noqa: F401
from stcommands.toolbar import COMMANDS, register  # noqa: F401
from sttaskpanels.boundary import BoundaryPanel, edit_boundary  # noqa: F401
from sttaskpanels.tube import TubePanel  # noqa: F401
from sttaskpanels.validate import ValidatePanel  # noqa: F401

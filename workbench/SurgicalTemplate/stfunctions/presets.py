"""The sleeve catalogue: the project's presets and the user's own file."""
import os

import FreeCAD as App

import st_bridge


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


def preset(name_or_sizes):
    """A preset's sizes: a dict as it is, or the catalogue's preset of that name (case ignored)."""
    if isinstance(name_or_sizes, dict):
        return name_or_sizes
    return st_bridge.kernel().find_sleeve_preset(sleeve_presets(), str(name_or_sizes))

"""The sleeve catalogue: the project's presets and the user's own file."""
import os

import FreeCAD as App

import st_bridge


def sleeve_presets():
    """The sleeve catalogue: the project's (data/sleeve-presets.json) and the user's own file
    <FreeCAD user data>/SurgicalTemplate/sleeve-presets.json, whose sleeves add to it or replace
    those of the same name. Each: {name, description, inner_radius, outer_radius, length, offset} (mm)."""
    return _catalogue(st_bridge.kernel().sleeve_presets)


def _catalogue(read):
    """The project's entries of one section (read() lists them) and the user's file's (read(path)), which
    add to them or replace those of the same name."""
    entries = {e["name"]: e for e in read()}
    mine = user_presets_path()
    if os.path.exists(mine):
        entries.update({e["name"]: e for e in read(mine)})
    return list(entries.values())


PREFERENCES = "User parameter:BaseApp/Preferences/Mod/SurgicalTemplate"


def preferred_slot():
    """(blade thickness, slot length) in mm for slots whose plan gives none: the preferences' (Edit >
    Preferences > Surgical Template), 0.89 and 16 by default. Read with or without the GUI."""
    p = App.ParamGet(PREFERENCES)
    return p.GetFloat("SlotBlade", 0.89), p.GetFloat("SlotLength", 16.0)


def user_presets_path():
    return os.path.join(App.getUserAppDataDir(), "SurgicalTemplate", "sleeve-presets.json")


def preset(name_or_sizes):
    """A preset's sizes: a dict as it is, or the catalogue's preset of that name (case ignored)."""
    if isinstance(name_or_sizes, dict):
        return name_or_sizes
    return st_bridge.kernel().find_sleeve_preset(sleeve_presets(), str(name_or_sizes))


def blade_presets():
    """The saw blades of the catalogue: the project's and those of the user's own file (as sleeve_presets).
    Each: {name, description, thickness, clearance} (mm)."""
    return _catalogue(st_bridge.kernel().blade_presets)


def blade(name_or_thickness):
    """A blade: a dict as it is, a thickness in mm (clearance 0.1), or the catalogue's blade of that name
    (case ignored); ValueError listing the names when there is none."""
    if isinstance(name_or_thickness, dict):
        return name_or_thickness
    if isinstance(name_or_thickness, (int, float)):
        return {"name": f"{float(name_or_thickness):g} mm", "thickness": float(name_or_thickness), "clearance": 0.1}
    return st_bridge.kernel().find_blade_preset(blade_presets(), str(name_or_thickness))

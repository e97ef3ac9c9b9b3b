"""A cutting guide's parts besides its tubes (Part::FeaturePython each, in the guide's Parts): a saw slot
on a planned cut plane and a label engraved into or embossed onto the outer surface, their properties the
case file's slot and label keys (docs/CASE-FORMAT.md). The guide builds them (the kernel places a slot's
housing over the template and lays a label's text on its outer surface); their own shapes show the plan:
a slot's blade slab over the cut, a label's text outlines at its place."""
import json
import os

import numpy as np

import FreeCAD as App
import Part

import st_bridge
from stobjects.base import Feature

CLOSED = {"both ends": ["start", "end"], "start": ["start"], "end": ["end"], "open": []}
LABEL_FONT = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf"   # the kernel's (kernel/occt/src/occt_text.cpp)
CAP_HEIGHT = 0.729   # DejaVu Sans: a capital H's height per unit of font size


def _vec(v):
    return [float(v.x), float(v.y), float(v.z)]


class Slot(Feature):
    kind = "Slot"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyPosition", "Origin", "Slot", "A point of the cut plane on the bone surface (mm)")
        self.add(obj, "App::PropertyDirection", "Normal", "Slot", "The cut plane's normal", App.Vector(0, 0, 1))
        self.add(obj, "App::PropertyDirection", "Travel", "Slot",
                 "The saw's travel in the plane, into the bone; zero: into the bone as the bone near the "
                 "origin gives it", App.Vector(0, 1, 0))
        self.add(obj, "App::PropertyLength", "Blade", "Slot", "Blade thickness", 0.89)
        self.add(obj, "App::PropertyLength", "Clearance", "Slot", "Gap on each side of the blade", 0.1)
        self.add(obj, "App::PropertyLength", "Length", "Slot", "The slot's extent across the travel, centred on "
                 "the origin", 16.0)
        self.add(obj, "App::PropertyLength", "Height", "Slot", "The housing's height above the template", 5.0)
        self.add(obj, "App::PropertyLength", "Wall", "Slot", "The housing's wall thickness", 3.0)
        if "Closed" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Closed", "Slot", "Which ends the housing closes")
            obj.Closed = list(CLOSED)
            obj.Closed = "both ends"
        if "BladePreset" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "BladePreset", "Slot",
                            "A saw blade from the catalogue: its thickness and clearance (custom: as typed)")
            obj.BladePreset = ["custom"]
        self.add(obj, "App::PropertyString", "BladeCatalogue", "Slot",
                 "The catalogue's blades when the slot was made (JSON: name -> [thickness, clearance])", "{}",
                 hidden=True)

    @staticmethod
    def set_blades(obj, blades):
        """The blades BladePreset offers: the catalogue's ({name, thickness, clearance} each)."""
        obj.BladeCatalogue = json.dumps({b["name"]: [b["thickness"], b["clearance"]] for b in blades})
        current = obj.BladePreset
        names = ["custom"] + [b["name"] for b in blades]
        obj.BladePreset = names
        obj.BladePreset = current if current in names else "custom"

    def onChanged(self, obj, prop):
        """A blade chosen from the catalogue sets the thickness and clearance."""
        if prop != "BladePreset" or "BladeCatalogue" not in obj.PropertiesList:
            return
        chosen = json.loads(obj.BladeCatalogue or "{}").get(obj.BladePreset)
        if chosen is None:
            return
        if abs(obj.Blade.Value - chosen[0]) > 1e-12:
            obj.Blade = chosen[0]
        if abs(obj.Clearance.Value - chosen[1]) > 1e-12:
            obj.Clearance = chosen[1]

    @staticmethod
    def spec(obj):
        s = {"name": obj.Label, "origin": _vec(obj.Origin), "normal": _vec(obj.Normal),
             "blade": float(obj.Blade.Value), "clearance": float(obj.Clearance.Value),
             "length": float(obj.Length.Value), "height": float(obj.Height.Value), "wall": float(obj.Wall.Value),
             "closed": CLOSED[obj.Closed]}
        if obj.Travel.Length > 0:
            s["direction"] = _vec(obj.Travel)
        return s

    def execute(self, obj):
        """The blade's slab over the planned cut: blade + 2 x clearance wide, the slot's length across
        the travel, from 2 mm into the bone to the housing's height over the origin."""
        n = App.Vector(obj.Normal)
        if n.Length == 0:
            raise ValueError(f"{obj.Label}: the cut plane's normal is zero")
        n.normalize()
        d = App.Vector(obj.Travel)
        d = d - n * d.dot(n)
        if d.Length < 1e-9:   # travel from the bone: shown along any direction in the plane
            d = n.cross(App.Vector(1, 0, 0) if abs(n.x) < 0.9 else App.Vector(0, 1, 0))
        d.normalize()
        e = n.cross(d)
        w = obj.Blade.Value + 2 * obj.Clearance.Value
        up = obj.Height.Value + 3.0
        corner = App.Vector(obj.Origin) - e * (obj.Length.Value / 2) - n * (w / 2) - d * up
        box = Part.makeBox(obj.Length.Value, w, up + 2.0)
        box.Placement = App.Placement(corner, App.Rotation(e, n, d, "ZXY"))   # (e, n, d) right-handed
        obj.Shape = box


class Label(Feature):
    kind = "Label"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyString", "Text", "Label", "The text, one line", "")
        self.add(obj, "App::PropertyPosition", "At", "Label", "Where the text is centred, on or near the outer surface")
        self.add(obj, "App::PropertyDirection", "Up", "Label", "The text's up direction", App.Vector(0, 0, 1))
        self.add(obj, "App::PropertyLength", "Height", "Label", "Cap height", 4.0)
        self.add(obj, "App::PropertyLength", "Depth", "Label", "Engraving depth or embossing height", 0.6)
        if "Mode" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Mode", "Label", "Engraved into or embossed onto the surface")
            obj.Mode = ["engrave", "emboss"]
            obj.Mode = "engrave"
        self.add(obj, "App::PropertyDirection", "Facing", "Label",
                 "Outward from the surface near At: the side the text is read from (its own shape only; the guide "
                 "lays the text on its outer surface)", App.Vector(0, -1, 0))

    @staticmethod
    def spec(obj):
        return {"name": obj.Name if not obj.Label else obj.Label, "text": obj.Text, "at": _vec(obj.At),
                "up": _vec(obj.Up), "height": float(obj.Height.Value), "depth": float(obj.Depth.Value),
                "mode": obj.Mode}

    def execute(self, obj):
        """The text's outlines in the plane through At facing out, reading across Up."""
        if not obj.Text.strip():
            raise ValueError(f"{obj.Label}: the label has no text")
        facing, up = App.Vector(obj.Facing), App.Vector(obj.Up)
        if facing.Length == 0 or up.Length == 0:
            raise ValueError(f"{obj.Label}: Up and Facing must not be zero")
        facing.normalize()
        up = up - facing * up.dot(facing)
        if up.Length < 1e-9:
            raise ValueError(f"{obj.Label}: Up runs along Facing")
        up.normalize()
        right = up.cross(facing)
        size = obj.Height.Value / CAP_HEIGHT
        if os.path.exists(LABEL_FONT):
            chars = Part.makeWireString(obj.Text, os.path.dirname(LABEL_FONT) + "/", os.path.basename(LABEL_FONT),
                                        size)
            edges = [e for char in chars for w in char for e in w.Edges]
        else:
            edges = []
        shape = Part.makeCompound(edges) if edges else Part.makeCompound([Part.makeLine(App.Vector(), right)])
        box = shape.BoundBox
        local = App.Vector((box.XMin + box.XMax) / 2, obj.Height.Value / 2, 0)
        placement = App.Placement(App.Vector(), App.Rotation(right, up, facing, "ZXY"))
        placement.Base = App.Vector(obj.At) - placement.Rotation.multVec(local)
        shape.Placement = placement
        obj.Shape = shape


def outward_normal(bone, at):
    """The bone's outward normal near `at`: the area-weighted normal of its triangles within 3 mm (or of
    the nearest vertex's), for a label's Facing."""
    V, F = st_bridge.bone_arrays(bone)
    at = np.asarray(at, dtype=float)
    corners = V[F]
    centres = corners.mean(axis=1)
    near = np.linalg.norm(centres - at, axis=1) < 3.0
    if not near.any():
        near = np.zeros(len(F), dtype=bool)
        near[np.argmin(np.linalg.norm(centres - at, axis=1))] = True
    n = np.cross(corners[near, 1] - corners[near, 0], corners[near, 2] - corners[near, 0]).sum(axis=0)
    length = np.linalg.norm(n)
    return App.Vector(*(n / length)) if length > 0 else App.Vector(0, 0, 1)

"""The drilling tube (Part::FeaturePython): a guide sleeve on a planned axis (Entry, Direction, radii,
Length, Offset; Depth and Preset since 0.2; Kind and the counterbore since 0.3), its solid from the
kernel's OpenCASCADE model."""
import FreeCAD as App
import Part

import st_bridge
from stobjects.base import Feature


class Tube(Feature):
    kind = "Tube"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyVector", "Entry", "Tube", "Where the planned axis meets the bone (mm)")
        self.add(obj, "App::PropertyVector", "Direction", "Tube", "Drilling direction, into the bone",
                 App.Vector(0, 0, -1))
        self.add(obj, "App::PropertyLength", "InnerRadius", "Tube", "Bore radius: the drill's path", 1.1)
        self.add(obj, "App::PropertyLength", "OuterRadius", "Tube", "Sleeve outer radius", 2.0)
        self.add(obj, "App::PropertyLength", "Length", "Tube", "Sleeve length along the axis", 5.0)
        self.add(obj, "App::PropertyLength", "Offset", "Tube",
                 "Distance from the entry back along the axis to the sleeve's lower end", 0.0)
        self.properties_since_0_2(obj)

    def properties_since_0_2(self, obj):
        """Properties that documents saved by the first version lack (added on restore)."""
        self.add(obj, "App::PropertyLength", "Depth", "Plan",
                 "Planned drilling depth into the bone beyond the entry (drill protocol); 0: not planned", 0.0)
        self.add(obj, "App::PropertyString", "Preset", "Plan", "The sleeve preset the sizes came from", "")
        self.properties_since_0_3(obj)

    def properties_since_0_3(self, obj):
        """A tube may be a fixation pin's, with a counterbore for a screw's head (added on restore)."""
        if "Kind" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Kind", "Tube", "What it guides: a drill or a fixation pin")
            obj.Kind = ["sleeve", "pin"]
            obj.Kind = "sleeve"
        self.add(obj, "App::PropertyLength", "CounterboreRadius", "Tube",
                 "Radius of the hole for a screw's head, from the sleeve's top down; 0: none", 0.0)
        self.add(obj, "App::PropertyLength", "CounterboreDepth", "Tube", "Depth of that hole", 0.0)

    def onDocumentRestored(self, obj):
        super().onDocumentRestored(obj)
        self.properties_since_0_2(obj)

    def spec(self, obj):
        s = {"name": obj.Label, "entry": st_bridge.vec(obj.Entry), "direction": st_bridge.vec(obj.Direction),
             "inner_radius": float(obj.InnerRadius.Value), "outer_radius": float(obj.OuterRadius.Value),
             "length": float(obj.Length.Value), "offset": float(obj.Offset.Value)}
        depth = float(obj.Depth.Value) if hasattr(obj, "Depth") else 0.0
        if depth > 0:
            s["depth"] = depth
        if hasattr(obj, "Kind"):
            s["kind"] = obj.Kind
            if obj.CounterboreRadius.Value > 0 or obj.CounterboreDepth.Value > 0:
                s["counterbore"] = {"radius": float(obj.CounterboreRadius.Value),
                                    "depth": float(obj.CounterboreDepth.Value)}
        return s

    def execute(self, obj):
        s = self.spec(obj)
        k = st_bridge.kernel()
        if getattr(k, "has_occt", False):
            # The kernel's OpenCASCADE model of the sleeve: the same definition the guide uses.
            shape = Part.Shape()
            shape.importBrepFromString(k.sleeve_brep(s["entry"], s["direction"], s["inner_radius"],
                                                     s["outer_radius"], s["length"], s["offset"], s["name"]))
        else:
            d = App.Vector(*s["direction"]).normalize()
            base = App.Vector(*s["entry"]) - d * s["offset"]
            up = -d
            outer = Part.makeCylinder(s["outer_radius"], s["length"], base, up)
            shape = outer.cut(Part.makeCylinder(s["inner_radius"], s["length"], base, up)).Solids[0]
        obj.Shape = shape

"""The drilling tube (Part::FeaturePython): a guide sleeve on a planned axis (Entry, Direction, diameters,
Length, Offset; Depth and Preset since 0.2; Kind and the counterbore since 0.3), its solid from the
kernel's OpenCASCADE model. Sizes are diameters as the catalogue, drawings and vendors give them (the case
file keeps radii); documents from before 0.4, with radii and plain vectors, are migrated on restore."""
import FreeCAD as App
import Part

import st_bridge
from stobjects.base import Feature

# Properties renamed in 0.4: a radius became a diameter (its value and any expression doubled).
_RADII = (("InnerRadius", "InnerDiameter"), ("OuterRadius", "OuterDiameter"),
          ("CounterboreRadius", "CounterboreDiameter"))
# Properties retyped in 0.4: (name, type, tooltip); their values kept.
_AXIS = (("Entry", "App::PropertyPosition", "Where the planned axis meets the bone (mm)"),
         ("Direction", "App::PropertyDirection", "Drilling direction, into the bone"))
_SIZES = {"InnerDiameter": "Bore diameter: the drill's path",
          "OuterDiameter": "Sleeve outer diameter",
          "CounterboreDiameter": "Diameter of the hole for a screw's head, from the sleeve's top down; 0: none"}


class Tube(Feature):
    kind = "Tube"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, _AXIS[0][1], "Entry", "Tube", _AXIS[0][2])
        self.add(obj, _AXIS[1][1], "Direction", "Tube", _AXIS[1][2], App.Vector(0, 0, -1))
        self.add(obj, "App::PropertyLength", "InnerDiameter", "Tube", _SIZES["InnerDiameter"], 2.2)
        self.add(obj, "App::PropertyLength", "OuterDiameter", "Tube", _SIZES["OuterDiameter"], 4.0)
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
        if "CounterboreRadius" not in obj.PropertiesList:   # (a 0.3 document: migrated below)
            self.add(obj, "App::PropertyLength", "CounterboreDiameter", "Tube", _SIZES["CounterboreDiameter"], 0.0)
        self.add(obj, "App::PropertyLength", "CounterboreDepth", "Tube", "Depth of that hole", 0.0)

    @staticmethod
    def migrate_to_0_4(obj):
        """Radii become diameters (values doubled, expressions wrapped in 2 * (...)); Entry and Direction
        become a position and a direction. Returns the names migrated."""
        done = []
        expressions = {path.lstrip("."): e for path, e in obj.ExpressionEngine}
        for old, new in _RADII:
            if old not in obj.PropertiesList:
                continue
            value, expression = 2.0 * float(getattr(obj, old).Value), expressions.get(old)
            if expression:
                obj.setExpression(old, None)
            obj.removeProperty(old)
            obj.addProperty("App::PropertyLength", new, "Tube", _SIZES[new])
            setattr(obj, new, value)
            if expression:
                obj.setExpression(new, f"2 * ({expression})")
            done.append(old)
        for name, kind, tip in _AXIS:
            if name in obj.PropertiesList and obj.getTypeIdOfProperty(name) != kind:
                value, expression = App.Vector(getattr(obj, name)), expressions.get(name)
                if expression:
                    obj.setExpression(name, None)
                obj.removeProperty(name)
                obj.addProperty(kind, name, "Tube", tip)
                setattr(obj, name, value)
                if expression:
                    obj.setExpression(name, expression)
                done.append(name)
        return done

    def onDocumentRestored(self, obj):
        super().onDocumentRestored(obj)
        self.properties_since_0_2(obj)
        migrated = self.migrate_to_0_4(obj)
        if migrated:
            App.Console.PrintMessage(f"Surgical Template: tube {obj.Label}: {', '.join(migrated)} migrated to "
                                     "diameters and a position and direction (0.4)\n")

    def spec(self, obj):
        s = {"name": obj.Label, "entry": st_bridge.vec(obj.Entry), "direction": st_bridge.vec(obj.Direction),
             "inner_radius": float(obj.InnerDiameter.Value) / 2.0, "outer_radius": float(obj.OuterDiameter.Value) / 2.0,
             "length": float(obj.Length.Value), "offset": float(obj.Offset.Value)}
        depth = float(obj.Depth.Value) if hasattr(obj, "Depth") else 0.0
        if depth > 0:
            s["depth"] = depth
        if hasattr(obj, "Kind"):
            s["kind"] = obj.Kind
            if obj.CounterboreDiameter.Value > 0 or obj.CounterboreDepth.Value > 0:
                s["counterbore"] = {"radius": float(obj.CounterboreDiameter.Value) / 2.0,
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

"""The boundary: control points on a bone (Part::FeaturePython); its shape is the closed curve
through them on the bone's surface, traced by the kernel."""
import FreeCAD as App
import Part

import st_bridge
from stobjects.base import Feature


class Boundary(Feature):
    kind = "Boundary"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyLink", "Bone", "Boundary", "The bone mesh the points lie on")
        self.add(obj, "App::PropertyVectorList", "Points", "Boundary",
                 "Control points around the region, in order (mm); the loop closes by itself")
        self.add(obj, "App::PropertyVector", "Inside", "Boundary", "A point inside the region to keep (mm)")
        self.add(obj, "App::PropertyBool", "UseInside", "Boundary",
                 "Keep the side holding Inside; otherwise the smaller side", False)

    @staticmethod
    def curve(bone, points):
        """The closed curve on the bone's surface through the control points, as points (the last
        joins the first); the boundary panel previews exactly this."""
        V, F = st_bridge.bone_arrays(bone)
        curve = st_bridge.kernel().trace_surface_curve(V, F, [st_bridge.vec(p) for p in points])
        return [App.Vector(*map(float, p)) for p in curve]

    def execute(self, obj):
        if obj.Bone is None or len(obj.Points) < 3:
            obj.Shape = Part.Shape()
            return
        pts = self.curve(obj.Bone, obj.Points)
        obj.Shape = Part.makePolygon(pts + [pts[0]])

"""The template (Mesh::FeaturePython): the shell the kernel designs inside a boundary (Thickness,
Clearance, Resolution); a kernel failure raises in execute() and the object keeps its last good mesh.
Insertion (Auto, Direction, None): along the least-undercut direction or InsertionDirection the kernel
blocks the undercuts out, hangs a skirt where the border lies where the bone turns under, and checks
that the finished guide comes off (UndercutArea, BlockedOutVolume, SkirtArea, Removable hold the results) and measures how firmly the seated guide is held pressed along it
(StabilityScore, 0..1, st/validate/stability.h); None keeps the bone's surface as it is, with no analysis."""
import FreeCAD as App

import st_bridge
from stobjects.base import Feature

INSERTION_MODES = ["Auto", "Direction", "None"]


def insertion_argument(obj):
    """The kernel's insertion argument for a template: "auto", a direction, or None (no analysis, as
    for documents made before the property existed)."""
    mode = getattr(obj, "Insertion", "None")
    if mode == "Auto":
        return "auto"
    if mode == "Direction":
        return st_bridge.vec(obj.InsertionDirection)
    return None


class Template(Feature):
    kind = "Template"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyLink", "Boundary", "Template", "The boundary on the bone")
        self.add(obj, "App::PropertyLength", "Thickness", "Template", "Distance from inner to outer surface", 2.5)
        self.add(obj, "App::PropertyLength", "Clearance", "Template",
                 "Gap between bone and inner surface (printing and fit tolerance)", 0.0)
        self.add(obj, "App::PropertyLength", "Resolution", "Template",
                 "Cell size of the distance field for the outer surface; 0 picks thickness / 8", 0.0)
        self.add(obj, "App::PropertyInteger", "SamplingStep", "Template",
                 "Border points between samples of the outer cut; 0 picks one", 0)
        if "Insertion" not in obj.PropertiesList:
            obj.addProperty("App::PropertyEnumeration", "Insertion", "Insertion",
                            "Auto: the direction with the least undercut; Direction: InsertionDirection; "
                            "None: no analysis")
            obj.Insertion = INSERTION_MODES
            obj.Insertion = "None"
        self.add(obj, "App::PropertyVector", "InsertionDirection", "Insertion",
                 "The direction in which the guide moves onto the bone (with Insertion = Direction)",
                 App.Vector(0, 0, -1))
        self.add(obj, "App::PropertyArea", "UndercutArea", "Result",
                 "Bone area under the template the guide cannot reach along its insertion direction "
                 "(before block-out)", 0.0, readonly=True)
        self.add(obj, "App::PropertyVolume", "BlockedOutVolume", "Result",
                 "Volume the block-out fills over the bone's undercuts", 0.0, readonly=True)
        self.add(obj, "App::PropertyArea", "SkirtArea", "Result",
                 "Area of the skirt hung along the insertion direction where the drawn border lies where the "
                 "bone turns under (0 where none is needed or it could not be hung)", 0.0, readonly=True)
        self.add(obj, "App::PropertyVector", "InsertionUsed", "Result",
                 "The insertion direction of the last design (the least-undercut one with Auto)",
                 App.Vector(0, 0, 0), readonly=True)
        self.add(obj, "App::PropertyBool", "Removable", "Result",
                 "The guide comes off 20 mm against its insertion direction without meeting the bone",
                 False, readonly=True)
        self.add(obj, "App::PropertyFloat", "StabilityScore", "Result",
                 "How firmly the contacts hold the guide pressed along its insertion direction: 0 when it can "
                 "slide or turn, 1 when it can only lift off (Validate shows the free motions)", 0.0, readonly=True)
        self.add(obj, "App::PropertyInteger", "InnerFaces", "Result",
                 "The first facets that form the inner surface (the seat on the bone)", 0, readonly=True)
        self.add(obj, "App::PropertyString", "Status", "Result", "What the kernel reported", "", readonly=True)

    def execute(self, obj):
        b = obj.Boundary
        if b is None or b.Bone is None:
            raise ValueError(f"{obj.Label}: no boundary on a bone")
        V, F = st_bridge.bone_arrays(b.Bone)
        k = st_bridge.kernel()
        r = st_bridge.call(k.design_template, V, F, [st_bridge.vec(p) for p in b.Points],
                           float(obj.Thickness.Value), clearance=float(obj.Clearance.Value),
                           resolution=float(obj.Resolution.Value), sampling_step=int(obj.SamplingStep),
                           inside=st_bridge.vec(b.Inside) if b.UseInside else None,
                           fit=False,  # the solid check, not the fit statistics (Validate inspects)
                           insertion=insertion_argument(obj))
        obj.Mesh = st_bridge.arrays_to_mesh(*r["shell"])
        if "insertion" not in r and "InsertionUsed" in obj.PropertiesList:
            obj.InsertionUsed = App.Vector(0, 0, 0)
        obj.InnerFaces = int(r["inner_faces"])
        self.drop_thickness_map(obj)
        obj.Status = f"{r['solid']['summary']}; {r['times']['initial_template_generation']:.3f} s"
        # The covered bone and what of it is hidden, for the undercut map (in memory, not saved).
        self.undercut = (r["insertion"]["region"], r["insertion"]["hidden"]) if "insertion" in r else None
        self.stability = r.get("stability")  # contacts, free motions, press point (in memory)
        if "StabilityScore" in obj.PropertiesList:
            obj.StabilityScore = float(self.stability["score"]) if self.stability else 0.0
        if "insertion" in r and "UndercutArea" in obj.PropertiesList:
            ins = r["insertion"]
            obj.UndercutArea = float(ins["undercut_area_mm2"])
            d = ins["direction"]
            obj.Status += (f"; undercut {ins['undercut_area_mm2']:.1f} mm^2 along ({d[0]:.3f}, {d[1]:.3f}, "
                           f"{d[2]:.3f})")
            if "InsertionUsed" in obj.PropertiesList:
                obj.InsertionUsed = App.Vector(*[float(x) for x in d])
            if "SkirtArea" in obj.PropertiesList:
                obj.SkirtArea = float(ins.get("skirt_area_mm2", 0.0))
            if ins.get("skirt_faces"):
                obj.Status += f"; skirt {ins['skirt_area_mm2']:.1f} mm^2 down to {ins['skirt_depth_mm']:.1f} mm"
            if ins.get("skirt_dropped"):
                obj.Status += "; no skirt: the guide ends where the bone turns under"
                App.Console.PrintWarning(f"{obj.Label}: the guide ends where the bone turns under, without the "
                                         f"skirt down to the drawn border (with it: {ins['skirt_dropped']})\n")
            if "Removable" in obj.PropertiesList:
                obj.BlockedOutVolume = float(ins["blocked_out_volume_mm3"])
                obj.Removable = bool(ins.get("removable", False))
                if ins.get("removable"):
                    obj.Status += "; comes off along it"
                elif ins.get("blocking"):
                    p = ins["blocking"][0]
                    obj.Status += f"; meets the bone coming off near ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f})"
        if self.stability:
            obj.Status += f"; stability {self.stability['score']:.2f}"

"""Document objects of the workbench: parametric features that recompute through the kernel.

  Boundary  Part::FeaturePython  control points on a bone; shape: the closed curve on its surface
  Template  Mesh::FeaturePython  the template shell of a boundary (Thickness, Clearance, Resolution)
  Tube      Part::FeaturePython  a drilling sleeve (Entry, Direction, radii, Length, Offset)
  Guide     Mesh::FeaturePython  the final guide: the shell with its tubes merged and bored

The bone is a plain Mesh::Feature. A kernel failure raises in execute(): FreeCAD marks the object
as failed and reports the message; the object keeps its last good result.
"""
import FreeCAD as App
import Part

import st_bridge


class _Feature:
    """Proxy base: no state of its own (everything is in properties), so saving and restoring
    documents needs nothing but the class (FreeCAD 0.20 uses __getstate__, 1.x dumps)."""

    kind = "Feature"

    def __init__(self, obj):
        obj.Proxy = self

    def __getstate__(self):
        return None

    def __setstate__(self, state):
        return None

    def dumps(self):
        return None

    def loads(self, state):
        return None

    @staticmethod
    def drop_thickness_map(obj):
        """A new mesh makes the colours of the last inspection meaningless (SurgicalTemplate.inspect)."""
        if "ThicknessMap" in obj.PropertiesList and len(obj.ThicknessMap):
            obj.ThicknessMap = []
            if App.GuiUp:
                obj.ViewObject.Coloring = False

    @staticmethod
    def add(obj, kind, name, group, doc, value=None, hidden=False, readonly=False):
        """Adds a property with its default; one that exists already keeps its value."""
        if name not in obj.PropertiesList:
            obj.addProperty(kind, name, group, doc)
            if value is not None:
                setattr(obj, name, value)
        mode = (1 if readonly else 0) | (2 if hidden else 0)
        if mode:
            obj.setEditorMode(name, mode)


class Boundary(_Feature):
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


class Template(_Feature):
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
                           fit=False)  # the solid check, not the fit statistics (Validate inspects)
        obj.Mesh = st_bridge.arrays_to_mesh(*r["shell"])
        obj.InnerFaces = int(r["inner_faces"])
        self.drop_thickness_map(obj)
        obj.Status = f"{r['solid']['summary']}; {r['times']['total']:.3f} s"


class Tube(_Feature):
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

    def onDocumentRestored(self, obj):
        self.properties_since_0_2(obj)

    def spec(self, obj):
        s = {"name": obj.Label, "entry": st_bridge.vec(obj.Entry), "direction": st_bridge.vec(obj.Direction),
             "inner_radius": float(obj.InnerRadius.Value), "outer_radius": float(obj.OuterRadius.Value),
             "length": float(obj.Length.Value), "offset": float(obj.Offset.Value)}
        depth = float(obj.Depth.Value) if hasattr(obj, "Depth") else 0.0
        if depth > 0:
            s["depth"] = depth
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


class Guide(_Feature):
    kind = "Guide"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyLink", "Shell", "Guide", "The template shell")
        self.add(obj, "App::PropertyLinkList", "Tubes", "Guide", "The drilling tubes merged into the shell")
        self.add(obj, "App::PropertyLength", "Tolerance", "Guide", "Chordal tolerance of sleeves and bores", 0.01)
        self.add(obj, "App::PropertyString", "Status", "Result", "What the kernel reported", "", readonly=True)

    def execute(self, obj):
        shell = obj.Shell
        if shell is None or shell.Boundary is None or shell.Boundary.Bone is None:
            raise ValueError(f"{obj.Label}: no template shell on a bone")
        k = st_bridge.kernel()
        V, F = st_bridge.mesh_to_arrays(shell.Mesh)
        if len(F) < shell.InnerFaces or shell.InnerFaces <= 0:
            raise ValueError(f"{obj.Label}: the shell '{shell.Label}' has not been designed yet")
        BV, BF = st_bridge.bone_arrays(shell.Boundary.Bone)
        tubes = [t.Proxy.spec(t) for t in obj.Tubes]
        if tubes:
            g = st_bridge.call(k.add_tubes, V, F, int(shell.InnerFaces), BV, BF, tubes,
                               chordal_tolerance=float(obj.Tolerance.Value),
                               clearance=float(shell.Clearance.Value))
            V, F = g["mesh"]
            seconds = g["seconds"]
        else:
            seconds = 0.0
        report = st_bridge.call(k.check_solid, V, F)
        if not report["valid"]:
            raise RuntimeError(f"{obj.Label}: the guide failed its check: {report['summary']}")
        obj.Mesh = st_bridge.arrays_to_mesh(V, F)
        self.drop_thickness_map(obj)
        obj.Status = f"{report['summary']}; tubes {seconds:.3f} s"


class ViewProvider:
    """Icons and children in the tree."""

    def __init__(self, vobj, icon):
        vobj.Proxy = self
        self.icon = icon

    def attach(self, vobj):
        self.Object = vobj.Object

    def getIcon(self):
        import os
        return os.path.join(os.path.dirname(os.path.abspath(__file__)), "icons", self.icon)

    def claimChildren(self):
        o = self.Object
        kids = []
        for name in ("Boundary", "Shell"):
            if hasattr(o, name) and getattr(o, name) is not None:
                kids.append(getattr(o, name))
        if hasattr(o, "Tubes"):
            kids += list(o.Tubes)
        return kids

    # Edit mode. A boundary's editor is the boundary panel on its points (st_panels.edit_boundary);
    # a double-click in the tree enters edit mode 0 (FreeCAD's default for Part features, so there is no
    # doubleClicked here: in 0.20 any doubleClicked, even one returning None, replaces the default for all
    # kinds). For other kinds these return None, which leaves FreeCAD's default behaviour.
    def _editable(self):
        return getattr(getattr(getattr(self, "Object", None), "Proxy", None), "kind", "") == "Boundary"

    def setEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        import st_panels
        return st_panels.edit_boundary(vobj.Object)

    def unsetEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        import st_panels
        st_panels.BoundaryPanel.edit_ended(vobj.Object)
        return True

    def setupContextMenu(self, vobj, menu):
        if self._editable():
            import FreeCADGui
            action = menu.addAction("Edit boundary points")
            action.triggered.connect(
                lambda: FreeCADGui.getDocument(vobj.Object.Document.Name).setEdit(vobj.Object.Name, 0))

    def __getstate__(self):
        return {"icon": self.icon}

    def __setstate__(self, state):
        self.icon = (state or {}).get("icon", "")

    def dumps(self):
        return self.__getstate__()

    def loads(self, state):
        self.__setstate__(state)

"""What a template shows of its insertion in the 3D view: an arrow along the direction in which the
guide goes onto the bone (InsertionUsed), and on demand the undercut map: the covered bone, red where
the guide cannot reach it along that direction (before block-out), green where it can; and the
stability: contacts (green points), free motions (arrows: slides along, turns about their axis) and
where to press (a blue point and arrow). Coin nodes
under the template's view provider, not document objects: showing them changes nothing to undo."""
import FreeCAD as App
from pivy import coin

ARROW = (0.95, 0.60, 0.05)
CONTACT = (0.10, 0.75, 0.25)
FREE = (0.90, 0.20, 0.60)
PRESS = (0.15, 0.35, 0.95)
HIDDEN = (0.85, 0.15, 0.12)
REACHED = (0.20, 0.70, 0.30)


def arrow_node(tail, tip, rgb, width):
    """A Coin arrow from `tail` to `tip` (App.Vector): the shaft and four strokes of the head."""
    d = tip - tail
    length = d.Length
    d = d.normalize() if length > 0 else App.Vector(0, 0, 1)
    side = d.cross(App.Vector(1, 0, 0) if abs(d.x) < 0.9 else App.Vector(0, 1, 0)).normalize()
    other = d.cross(side)
    head = 0.25 * length
    points = [tail, tip]
    for s in (side, -side, other, -other):
        points += [tip, tip - d * head + s * (0.4 * head)]
    sep = coin.SoSeparator()
    style = coin.SoDrawStyle()
    style.lineWidth = width
    colour = coin.SoBaseColor()
    colour.rgb = rgb
    coords = coin.SoCoordinate3()
    coords.point.setValues(0, len(points), [(p.x, p.y, p.z) for p in points])
    lines = coin.SoLineSet()
    lines.numVertices.setValues(0, 5, [2] * 5)
    for node in (style, colour, coords, lines):
        sep.addChild(node)
    return sep


class InsertionOverlay:
    """The arrow and the undercut map of one template's view provider."""

    def __init__(self, vobj):
        self.root = coin.SoSeparator()
        self.root.setName("InsertionOverlay")
        pick = coin.SoPickStyle()
        pick.style = coin.SoPickStyle.UNPICKABLE
        self.root.addChild(pick)
        self.arrow = coin.SoSwitch()
        self.arrow.setName("InsertionArrow")
        self.map = coin.SoSwitch()
        self.map.setName("UndercutMap")
        self.stability = coin.SoSwitch()
        self.stability.setName("StabilityOverlay")
        self.root.addChild(self.arrow)
        self.root.addChild(self.map)
        self.root.addChild(self.stability)
        self.stability_counts = {"contacts": 0, "motions": 0, "press": 0}
        vobj.RootNode.addChild(self.root)
        self.map_faces = 0

    def update(self, obj):
        """The arrow for obj.InsertionUsed over obj's mesh (none without a direction or a mesh)."""
        self.arrow.removeAllChildren()
        self.arrow.whichChild = coin.SO_SWITCH_NONE
        used = getattr(obj, "InsertionUsed", None)
        box = obj.Mesh.BoundBox if obj.Mesh.CountFacets else None
        if used is None or used.Length == 0 or box is None:
            return
        d = App.Vector(used).normalize()  # a copy: the property's own vector would notify a change
        centre = box.Center
        half = 0.5 * box.DiagonalLength
        length = max(10.0, 0.6 * half)
        tip = centre - d * (0.55 * half)
        tail = tip - d * length
        self.arrow.addChild(arrow_node(tail, tip, ARROW, 4))
        self.arrow.whichChild = 0 if obj.ViewObject.Visibility else coin.SO_SWITCH_NONE

    def show_stability(self, stability, on=True):
        """The kernel's stability analysis (analyse_stability's dict): its contacts as green points, its
        free motions as arrows at the centroid (a turn: its axis, arrow-headed), the press point in
        blue with an arrow along the insertion direction; on=False hides them."""
        self.stability.removeAllChildren()
        self.stability.whichChild = coin.SO_SWITCH_NONE
        self.stability_counts = {"contacts": 0, "motions": 0, "press": 0}
        if not on or not stability:
            return
        sep = coin.SoAnnotation()  # drawn over the guide: the contacts lie under it, on the bone side
        points = [tuple(float(c) for c in p) for p in stability["contact_points"]]
        if points:
            style = coin.SoDrawStyle()
            style.pointSize = 4
            colour = coin.SoBaseColor()
            colour.rgb = CONTACT
            coords = coin.SoCoordinate3()
            coords.point.setValues(0, len(points), points)
            cloud = coin.SoPointSet()
            for node in (style, colour, coords, cloud):
                sep.addChild(node)
        length = max(5.0, float(stability["scale_mm"]))
        centre = App.Vector(*stability["centroid"])
        for m in stability["free_motions"]:
            d = App.Vector(*m["direction"])
            if m["kind"] in ("turn", "screw"):
                foot = App.Vector(*m["point"])
                foot = foot + d * (centre - foot).dot(d)  # the axis point nearest the centroid
                sep.addChild(arrow_node(foot - d * length, foot + d * length, FREE, 2))
            else:
                sep.addChild(arrow_node(centre, centre + d * length, FREE, 3))
            self.stability_counts["motions"] += 1
        press = App.Vector(*stability["press_point"])
        push = App.Vector(*stability["direction"])  # the insertion direction: the finger pushes along it
        sep.addChild(arrow_node(press - push * (0.6 * length), press, PRESS, 4))
        marker = coin.SoSeparator()
        style = coin.SoDrawStyle()
        style.pointSize = 10
        colour = coin.SoBaseColor()
        colour.rgb = PRESS
        coords = coin.SoCoordinate3()
        coords.point.setValue(press.x, press.y, press.z)
        for node in (style, colour, coords, coin.SoPointSet()):
            marker.addChild(node)
        sep.addChild(marker)
        self.stability_counts["press"] = 1
        self.stability_counts["contacts"] = len(points)
        self.stability.addChild(sep)
        self.stability.whichChild = 0

    def show_map(self, region, hidden, on=True):
        """The undercut map of the covered bone `region` ((vertices, triangles) arrays) with `hidden`
        (per face, the fraction the guide cannot reach); on=False hides it."""
        self.map.removeAllChildren()
        self.map.whichChild = coin.SO_SWITCH_NONE
        self.map_faces = 0
        if not on or region is None:
            return
        V, F = region
        sep = coin.SoSeparator()
        offset = coin.SoPolygonOffset()  # over the template's inner surface, which copies the bone
        offset.factor = -2.0
        offset.units = -2.0
        binding = coin.SoMaterialBinding()
        binding.value = coin.SoMaterialBinding.PER_FACE
        material = coin.SoMaterial()
        material.diffuseColor.setValues(0, len(F), [HIDDEN if h > 0 else REACHED for h in hidden])
        coords = coin.SoCoordinate3()
        coords.point.setValues(0, len(V), [tuple(float(c) for c in p) for p in V])
        faces = coin.SoIndexedFaceSet()
        index = []
        for t in F:
            index += [int(t[0]), int(t[1]), int(t[2]), -1]
        faces.coordIndex.setValues(0, len(index), index)
        for node in (offset, binding, material, coords, faces):
            sep.addChild(node)
        self.map.addChild(sep)
        self.map.whichChild = 0
        self.map_faces = len(F)

    def set_visible(self, on):
        """The arrow follows the template's visibility (FreeCAD hides the view provider's display mode,
        not nodes added beside it); the map stays while it is asked for (a guide hides its template)."""
        if self.arrow.getNumChildren():
            self.arrow.whichChild = 0 if on else coin.SO_SWITCH_NONE

"""What the workbench's proxies share: the proxy base (no state of its own) and the kind of an object."""


# Called with each workbench object restored from a file: the GUI registers the one that gives an object
# saved without the GUI its view provider (InitGui.py, stviewproviders.view_feature.restore_view); the
# objects know nothing of the GUI.
RESTORE_HOOKS = []


class Feature:
    """Proxy base: no state of its own (everything is in properties), so saving and restoring
    documents needs nothing but the class (FreeCAD 0.20 uses __getstate__, 1.x dumps)."""

    kind = "Feature"

    def __init__(self, obj):
        obj.Proxy = self

    def onDocumentRestored(self, obj):
        for hook in RESTORE_HOOKS:
            hook(obj)

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
        """A new mesh makes the colours of the last inspection meaningless (SurgicalTemplate.inspect);
        the view provider turns the colouring off with them."""
        if "ThicknessMap" in obj.PropertiesList and len(obj.ThicknessMap):
            obj.ThicknessMap = []

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

def kind_of(obj):
    """The kind of a document object: its proxy's (Boundary, Template, Tube, Guide), 'Bone' for a plain
    mesh, '' for anything else."""
    return getattr(getattr(obj, "Proxy", None), "kind", "Bone" if getattr(obj, "TypeId", "") == "Mesh::Feature" else "")

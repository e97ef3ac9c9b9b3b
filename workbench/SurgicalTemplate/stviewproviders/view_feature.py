"""The view provider of every workbench object (boundary, template, tube, guide): its icon, its
children in the tree, the boundary's edit mode (the boundary task panel) and context menu, the
thickness map's colouring turned off when a recompute drops the map, and a template's insertion arrow
and undercut map (stviewproviders.insertion_view)."""
import os

import SurgicalTemplate_paths


class ViewProvider:
    """Icons and children in the tree."""

    def __init__(self, vobj, icon):
        vobj.Proxy = self
        self.icon = icon

    def attach(self, vobj):
        self.Object = vobj.Object
        self.overlay = None
        if getattr(getattr(vobj.Object, "Proxy", None), "kind", "") == "Template":
            from stviewproviders.insertion_view import InsertionOverlay
            self.overlay = InsertionOverlay(vobj)
            self.overlay.update(vobj.Object)

    def getIcon(self):
        return os.path.join(SurgicalTemplate_paths.ICONS, self.icon)

    def claimChildren(self):
        o = self.Object
        kids = []
        for name in ("Boundary", "Shell"):
            if hasattr(o, name) and getattr(o, name) is not None:
                kids.append(getattr(o, name))
        if hasattr(o, "Tubes"):
            kids += list(o.Tubes)
        return kids

    def updateData(self, obj, prop):
        """A recompute that drops the thickness map (stobjects.base.Feature.drop_thickness_map) turns
        its colouring off."""
        if prop == "ThicknessMap" and not len(obj.ThicknessMap) and obj.ViewObject.Coloring:
            obj.ViewObject.Coloring = False
        if prop in ("Mesh", "InsertionUsed") and getattr(self, "overlay", None) is not None:
            self.overlay.update(obj)

    def onChanged(self, vobj, prop):
        if prop == "Visibility" and getattr(self, "overlay", None) is not None:
            self.overlay.set_visible(vobj.Visibility)

    # Edit mode. A boundary's editor is the boundary panel on its points (sttaskpanels.boundary.edit_boundary);
    # a double-click in the tree enters edit mode 0 (FreeCAD's default for Part features, so there is no
    # doubleClicked here: in 0.20 any doubleClicked, even one returning None, replaces the default for all
    # kinds). For other kinds these return None, which leaves FreeCAD's default behaviour.
    def _editable(self):
        return getattr(getattr(getattr(self, "Object", None), "Proxy", None), "kind", "") == "Boundary"

    def setEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        from sttaskpanels import boundary
        return boundary.edit_boundary(vobj.Object)

    def unsetEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        from sttaskpanels import boundary
        boundary.BoundaryPanel.edit_ended(vobj.Object)
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

"""The view provider of every workbench object (boundary, template, tube, guide): its icon, its
children in the tree (shown again when it is deleted), its edit mode (the boundary, tube, template and
guide task panels) and context menu, tubes dragged onto or out of a guide in the tree, the
thickness map's colouring turned off when a recompute drops the map, and a template's insertion arrow
and undercut map (stviewproviders.insertion_view)."""
import os

import SurgicalTemplate_paths

GUIDE_COLOUR = (0.20, 0.45, 0.85)


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
        kids += list(getattr(o, "Parts", []))
        if self._kind() == "Guide":
            from stobjects.case_info import case_info_of
            info = case_info_of(o)
            if info is not None:
                kids.append(info)
        return kids

    def onDelete(self, vobj, subelements):
        """Deleting a guide or template shows again what it hid (its shell and tubes, its boundary), as
        Part's Booleans show their operands; undo brings the object back."""
        for child in self.claimChildren():
            child.Visibility = True
        return True

    # Drag and drop in the tree: a tube, slot or label dropped on a guide joins it (a sleeve merged and its
    # bore cut, a slot cut in its housing, a label engraved); one dragged out of a guide leaves it and shows
    # again. FreeCAD makes each drop one undo step.
    def canDragObjects(self):
        return self._kind() == "Guide"

    def canDragObject(self, obj):
        return self._kind() == "Guide" and (obj in self.Object.Tubes or obj in getattr(self.Object, "Parts", []))

    def dragObject(self, vobj, obj):
        guide = vobj.Object
        guide.Tubes = [t for t in guide.Tubes if t != obj]
        guide.Parts = [p for p in guide.Parts if p != obj]
        obj.Visibility = True
        guide.Document.recompute()

    def canDropObjects(self):
        return self._kind() == "Guide"

    def canDropObject(self, obj):
        kind = getattr(getattr(obj, "Proxy", None), "kind", "")
        g = self.Object
        return self._kind() == "Guide" and kind in ("Tube", "Slot", "Label") and obj not in g.Tubes \
            and obj not in getattr(g, "Parts", [])

    def dropObject(self, vobj, obj):
        guide = vobj.Object
        if getattr(getattr(obj, "Proxy", None), "kind", "") == "Tube":
            guide.Tubes = list(guide.Tubes) + [obj]
        else:
            guide.Parts = list(guide.Parts) + [obj]
        obj.Visibility = False
        guide.Document.recompute()

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

    # Edit mode: a double-click in the tree (or Edit > Toggle edit mode) opens the object's task panel
    # (sttaskpanels: boundary, tube, parameters). Mesh features (template, guide) open nothing on a
    # double-click by default, so it asks for edit mode here for every kind that has a panel.
    def _kind(self):
        return getattr(getattr(getattr(self, "Object", None), "Proxy", None), "kind", "")

    def _editable(self):
        return self._kind() in ("Boundary", "Tube", "Template", "Guide")

    def doubleClicked(self, vobj):
        if not self._editable():
            return False
        import FreeCADGui
        FreeCADGui.getDocument(vobj.Object.Document.Name).setEdit(vobj.Object.Name, 0)
        return True

    def setEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        if self._kind() == "Tube":
            from sttaskpanels.tube import edit_tube
            return edit_tube(vobj.Object)
        if self._kind() in ("Template", "Guide"):
            from sttaskpanels.parameters import edit_parameters
            return edit_parameters(vobj.Object)
        from sttaskpanels import boundary
        return boundary.edit_boundary(vobj.Object)

    def unsetEdit(self, vobj, mode=0):
        if mode != 0 or not self._editable():
            return None
        if self._kind() == "Boundary":
            from sttaskpanels import boundary
            boundary.BoundaryPanel.edit_ended(vobj.Object)
        return True

    def setupContextMenu(self, vobj, menu):
        if self._editable():
            import FreeCADGui
            text = {"Boundary": "Edit boundary points", "Tube": "Edit tube", "Template": "Edit template",
                    "Guide": "Edit guide"}[self._kind()]
            action = menu.addAction(text)
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


def restore_view(obj):
    """Gives a workbench object restored in the GUI its view provider when the document has none for it (a
    document made and saved without the GUI keeps no GuiDocument.xml): its icon, its children in the
    tree, its edit mode (as Draft restores its view objects). Its visibility comes with the document."""
    import FreeCAD as App
    kind = getattr(getattr(obj, "Proxy", None), "kind", "")
    vobj = getattr(obj, "ViewObject", None) if App.GuiUp else None
    if not kind or vobj is None or isinstance(vobj.Proxy, ViewProvider):
        return
    ViewProvider(vobj, f"SurgicalTemplate_{kind}.svg").attach(vobj)
    # Without a GuiDocument.xml entry the GUI hides what it restores once the document is read; shown
    # then as make_guide leaves it: a guide's shell and tubes hidden under it, everything else shown.
    under_a_guide = any(getattr(getattr(o, "Proxy", None), "kind", "") == "Guide" and
                        (o.Shell == obj or obj in o.Tubes or obj in getattr(o, "Parts", []))
                        for o in obj.Document.Objects)
    from PySide import QtCore
    QtCore.QTimer.singleShot(0, lambda: setattr(obj.ViewObject, "Visibility", not under_a_guide))
    if kind == "Guide":
        vobj.ShapeColor = GUIDE_COLOUR

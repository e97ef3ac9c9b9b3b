"""Renders a designed template on its bone in a real FreeCAD window (run under Xvfb when headless).

    QTWEBENGINE_DISABLE_SANDBOX=1 xvfb-run -a -s "-screen 0 1280x1024x24" \
        freecad examples/macros/render_template.py

Environment: ST_BONE (STL, or .stl.gz), ST_TEMPLATE (STL), ST_IMAGE (PNG to write),
ST_VIEW ("x,y,z" view direction, default isometric), ST_FRAME ("template" frames the template
only, for a close-up; default frames the bone around it too).
"""
import gzip
import os
import shutil
import tempfile

import FreeCAD as App
import FreeCADGui as Gui
import Mesh
from PySide import QtCore

bone_path = os.environ["ST_BONE"]
template_path = os.environ["ST_TEMPLATE"]
image = os.environ.get("ST_IMAGE", "template.png")
view = os.environ.get("ST_VIEW", "")
frame_template = os.environ.get("ST_FRAME", "") == "template"


def work():
    tmp = tempfile.mkdtemp()
    try:
        path = bone_path
        if path.endswith(".gz"):
            path = os.path.join(tmp, "bone.stl")
            with gzip.open(bone_path, "rb") as src, open(path, "wb") as dst:
                shutil.copyfileobj(src, dst)
        doc = App.newDocument("Render")
        tpl = doc.addObject("Mesh::Feature", "Template")
        tpl.Mesh = Mesh.Mesh(template_path)
        # Show the bone around the template only, so the view frames the template.
        bb = tpl.Mesh.BoundBox
        margin = 0.5 * max(bb.XLength, bb.YLength, bb.ZLength)
        bb.enlarge(margin)
        full = Mesh.Mesh(path)
        points, facets = full.Topology
        kept = [f for f in facets if all(bb.isInside(points[i]) for i in f)]
        bone = doc.addObject("Mesh::Feature", "Bone")
        bone.Mesh = Mesh.Mesh([[points[i] for i in f] for f in kept])
        doc.recompute()
        bone.ViewObject.ShapeColor = (0.93, 0.89, 0.80)
        tpl.ViewObject.ShapeColor = (0.20, 0.45, 0.85)
        Gui.updateGui()
        v = Gui.ActiveDocument.ActiveView
        if view:
            d = App.Vector(*[float(x) for x in view.split(",")])
            v.setViewDirection((d.x, d.y, d.z))
        else:
            v.viewIsometric()
        if frame_template:
            bone.ViewObject.Visibility = False
        v.fitAll()
        bone.ViewObject.Visibility = True
        Gui.updateGui()
        v.saveImage(image, 1000, 750, "White")
        App.closeDocument(doc.Name)
    finally:
        shutil.rmtree(tmp, ignore_errors=True)
        QtCore.QTimer.singleShot(0, Gui.getMainWindow().close)


QtCore.QTimer.singleShot(500, work)

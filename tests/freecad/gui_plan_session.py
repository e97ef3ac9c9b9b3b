"""Runs in a real FreeCAD window (under Xvfb in tests): a bone imported and a 3D Slicer plan put on it by
the commands, the guide validated in the Validate panel with its thickness map on screen, tubes added
in the tube panel from a sleeve preset with the direction from a second clicked point and from the
view; then the script FreeCAD recorded for all that (the lines its macro recorder writes, echoed in
the Python console) is replayed into fresh documents and must give the same tree.
Writes $ST_OUT/gui-plan-result.json; test_gui_plan.py asserts on it."""
import os
import sys
import time
import traceback

import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from gui_helpers import finish  # noqa: E402

out, examples = os.environ["ST_OUT"], os.environ["ST_EXAMPLES_DIR"]
result = {"errors": []}


def colour_fractions(path):
    """Fractions of the image's pixels that are the thickness map's green (seated) and red (in bone)."""
    image = QtGui.QImage(path)
    green = red = total = 0
    for y in range(0, image.height(), 3):
        for x in range(0, image.width(), 3):
            c = QtGui.QColor(image.pixel(x, y))
            total += 1
            green += c.green() > c.red() + 40 and c.green() > c.blue() + 40
            red += c.red() > c.green() + 80 and c.red() > c.blue() + 80
    return green / max(total, 1), red / max(total, 1)


def colour_near(path, rgb, tolerance=40):
    """Fraction of the image's pixels within `tolerance` (0..255, per channel) of the colour `rgb` (0..1)."""
    image = QtGui.QImage(path)
    target = [round(255 * c) for c in rgb]
    near = total = 0
    for y in range(0, image.height(), 2):
        for x in range(0, image.width(), 2):
            c = QtGui.QColor(image.pixel(x, y))
            total += 1
            near += all(abs(a - b) <= tolerance for a, b in zip((c.red(), c.green(), c.blue()), target))
    return near / max(total, 1)


def kind(o):
    return getattr(getattr(o, "Proxy", None), "kind", "")


def console():
    return [w for w in Gui.getMainWindow().findChildren(QtGui.QPlainTextEdit) if w.objectName() == "Python console"][0]


def recorded_lines(text):
    """The commands in the console's text, as the macro recorder writes them (comments dropped)."""
    lines = []
    for line in text.splitlines():
        if line.startswith(">>> ") or line.startswith("... "):
            code = line[4:]
            if code.strip() and not code.lstrip().startswith("#"):
                lines.append(code)
    return lines


def snapshot(doc):
    """What the replay must reproduce: the tree's objects and the guide's result."""
    guides = [o for o in doc.Objects if kind(o) == "Guide"]
    g = guides[0]
    return {"objects": sorted(o.Label for o in doc.Objects),
            "tubes": [[t.Label, list(t.Entry), list(t.Direction), t.Depth.Value, t.InnerDiameter.Value / 2, t.Preset]
                      for t in g.Tubes],
            "points": [list(p) for p in g.Shell.Boundary.Points],
            "state": list(g.State), "facets": g.Mesh.CountFacets, "volume": g.Mesh.Volume}


def work():
    try:
        Gui.activateWorkbench("SurgicalTemplateWorkbench")
        import st_commands
        import SurgicalTemplate
        result["commands"] = [c for c in Gui.listCommands() if c.startswith("SurgicalTemplate_")]
        case = SurgicalTemplate.st_bridge.kernel().read_case(os.path.join(examples, "cases", "vertebra-pedicle.json"))
        # Everything from here to the replay goes through the commands: FreeCAD records it.
        App.ParamGet("User parameter:BaseApp/Preferences/Macro").SetBool("ScriptToPyConsole", True)
        before = console().toPlainText()
        start = before.rfind("\n") + 1  # the prompt the first recorded command is written after
        st_commands.import_bone(case["bone"])  # Import bone after its file dialog
        doc = App.ActiveDocument
        doc_name = doc.Name
        bone = doc.Objects[0]
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(bone)
        # Import plan: the command's code path after its file dialog; the preset chooser answers.
        asked = []
        ok = st_commands.import_plan(os.path.join(examples, "plans", "vertebra-plan.mrk.json"), bone,
                                     lambda axes: asked.append([a["name"] for a in axes]) or "drill-2.5")
        guides = [o for o in doc.Objects if kind(o) == "Guide"]
        result["import"] = {"ok": ok, "asked": asked, "guides": len(guides),
                            "tubes": [t.Label for t in guides[0].Tubes] if guides else [],
                            "presets": [t.Preset for t in guides[0].Tubes] if guides else [],
                            "state": list(guides[0].State) if guides else []}
        guide = guides[0]
        # Validate: the panel's inspection and the thickness map on the guide.
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(guide)
        Gui.runCommand("SurgicalTemplate_Validate")
        panel = st_commands.ValidatePanel.last
        r = panel.result
        result["validate"] = {"error": panel.error, "passed": r["passed"], "summary": r["summary"],
                              "bores": r["bores"], "in_bone": r["vertices_in_bone"],
                              "colours": len(guide.ThicknessMap), "facets": guide.Mesh.CountFacets,
                              "coloring": guide.ViewObject.Coloring, "state": list(guide.State),
                              "removal": r["removal"] is not None and r["removal"]["removable"],
                              "removal_text": panel.form.removal.text()}
        # The colour bar, and a click on the guide reading the map there: a facet facing the viewer.
        view = Gui.ActiveDocument.ActiveView
        view.fitAll()
        Gui.updateGui()
        towards = -App.Vector(view.getViewDirection())
        width, height = view.getSize()
        readings = []
        for i, facet in enumerate(guide.Mesh.Facets):
            if facet.Normal.dot(towards) < 0.9 or facet.Area < 0.05:
                continue
            centre = sum((App.Vector(*p) for p in facet.Points), App.Vector()) * (1.0 / 3.0)
            x, y = view.getPointOnScreen(centre)
            if not (0 < x < width and 0 < y < height):
                continue
            got = panel.reader.read((x, y))
            if got is not None:
                readings.append({"facet": got[0], "point": list(got[1]), "distance": got[2], "aimed": i,
                                 "aimed_at": list(centre), "map": r["face_distance"][got[0]],
                                 "text": panel.form.reading.text()})
            if len(readings) == 3:
                break
        result["validate"]["readings"] = readings
        result["validate"]["bar"] = {"stops": panel.bar.stops, "shown": panel.bar.isVisible(),
                                     "height": panel.bar.height()}
        # The template's insertion arrow, and the undercut map the panel shows on demand.
        overlay = guide.Shell.ViewObject.Proxy.overlay
        result["validate"]["arrow"] = overlay.arrow.getNumChildren()
        panel.show_undercuts.setChecked(True)
        Gui.updateGui()
        result["validate"]["map_faces"] = overlay.map_faces
        result["validate"]["region_faces"] = len(guide.Shell.Proxy.undercut[0][1])
        panel.show_undercuts.setChecked(False)
        # The stability rows, and the contacts, free motions and press point the panel shows on demand.
        stab = r["stability"]
        panel.show_stability.setChecked(True)
        Gui.updateGui()
        result["validate"]["stability"] = {
            "text": panel.form.stability.text(), "motions_text": panel.form.free_motions.text(),
            "press_text": panel.form.press.text(), "shown": dict(overlay.stability_counts),
            "contacts": stab["contacts"] if stab else None, "motions": len(stab["free_motions"]) if stab else None,
            "score": stab["score"] if stab else None, "guide_score": guide.StabilityScore,
            "template_score": guide.Shell.StabilityScore, "template_status": guide.Shell.Status}
        panel.show_stability.setChecked(False)
        Gui.updateGui()
        result["validate"]["stability"]["hidden"] = dict(overlay.stability_counts)
        # Look at the inner surface from inside the bone: the seat is green.
        bone.ViewObject.Visibility = False
        view = Gui.ActiveDocument.ActiveView
        d = case["tubes"][0]["direction"]
        view.setViewDirection((-d[0], -d[1], -d[2]))
        view.fitAll()
        Gui.updateGui()
        path = os.path.join(out, "gui-thickness-map.png")
        view.saveImage(path, 800, 600, "White")
        result["map_shot"] = {"path": path, "green_red": colour_fractions(path)}
        Gui.getMainWindow().grab().save(os.path.join(out, "gui-validate-window.png"))   # the panel with its bar
        panel.show_map.setChecked(False)
        result["coloring_off"] = guide.ViewObject.Coloring
        # The contacts seen along the insertion direction, the bone hidden and the thickness map off:
        # pixels of the contacts' green with the overlay and without.
        panel.show_stability.setChecked(True)
        view.setViewDirection(tuple(stab["direction"]))
        view.fitAll()
        Gui.updateGui()
        shots = {}
        for name in ("on", "off"):
            path = os.path.join(out, f"gui-stability-{name}.png")
            view.saveImage(path, 800, 600, "White")
            shots[name] = colour_near(path, (0.10, 0.75, 0.25))
            panel.show_stability.setChecked(False)
            Gui.updateGui()
        result["validate"]["stability"]["green"] = shots
        panel.reject()

        # Tube panel: preset, direction from a second clicked point, then from the view.
        bone.ViewObject.Visibility = True
        guide.ViewObject.Visibility = False
        view.setViewDirection((0.0, 0.0, -1.0))  # from above (+z): the vertebra's top, where the points lie
        view.fitAll()
        Gui.updateGui()
        tubes_before = len(guide.Tubes)
        Gui.Selection.clearSelection()
        Gui.Selection.addSelection(guide)
        Gui.runCommand("SurgicalTemplate_AddTube")
        tp = st_commands.TubePanel.last
        names = [p["name"] for p in tp.presets]
        tp.preset.setCurrentIndex(names.index("kwire-2.0") + 1)
        tp.mode.setCurrentIndex(2)
        clicks = []
        for p in (case["tubes"][0]["entry"], case["boundary_points"][0]):
            pos = view.getPointOnScreen(App.Vector(*map(float, p)))
            pos = (int(pos[0]), int(pos[1]))
            hit = view.getObjectInfo(pos)
            clicks.append([hit["x"], hit["y"], hit["z"]] if hit and hit.get("Object") == bone.Name else None)
            tp.click(pos)
        tp.accept()
        new = [t for t in guide.Tubes][tubes_before:]
        result["second_point"] = {"clicks": clicks, "tubes": len(new),
                                  "direction": list(new[0].Direction) if new else None,
                                  "depth": new[0].Depth.Value if new else None,
                                  "sizes": [new[0].InnerDiameter.Value / 2, new[0].OuterDiameter.Value / 2, new[0].Length.Value,
                                            new[0].Offset.Value] if new else None,
                                  "preset": new[0].Preset if new else None,
                                  "kwire": [p for p in tp.presets if p["name"] == "kwire-2.0"][0]}
        Gui.runCommand("SurgicalTemplate_AddTube")
        tp = st_commands.TubePanel.last
        tp.mode.setCurrentIndex(1)
        pos = view.getPointOnScreen(App.Vector(*map(float, case["tubes"][1]["entry"])))
        result["view_click"] = tp.click((int(pos[0]), int(pos[1])))
        tp.accept()
        result["view_direction"] = {"tube": list(guide.Tubes[-1].Direction), "view": list(view.getViewDirection())}
        # Surface normal: the tube goes into the bone against the normal of the facet that was clicked.
        Gui.runCommand("SurgicalTemplate_AddTube")
        tp = st_commands.TubePanel.last
        tp.mode.setCurrentIndex(0)
        pos = view.getPointOnScreen(App.Vector(*map(float, case["boundary_points"][2])))
        hit = view.getObjectInfo((int(pos[0]), int(pos[1])))
        result["normal_click"] = tp.click((int(pos[0]), int(pos[1])))
        tp.accept()
        d = view.getViewDirection()
        point = App.Vector(hit["x"], hit["y"], hit["z"])
        facets = bone.Mesh.nearestFacetOnRay(tuple(point - d * 50), tuple(d))  # the first facet from outside
        facet = bone.Mesh.Facets[list(facets)[0]]
        result["normal"] = {"tube": list(guide.Tubes[-1].Direction), "facet_normal": list(facet.Normal)}
        doc.recompute()
        recorded = snapshot(doc)
        macro = recorded_lines(console().toPlainText()[start:])
        with open(os.path.join(out, "recorded-macro.FCMacro"), "w") as f:
            f.write("# Recorded by FreeCAD during the GUI test (tests/freecad/gui_plan_session.py)\n")
            f.write("\n".join(macro) + "\n")
        result["macro"] = macro
        # Sleeves on such ad-hoc axes may run into the bone: the guide then says so and keeps its last
        # good mesh; without them it is whole again.
        result["with_new_tubes"] = list(guide.State)
        guide.Tubes = guide.Tubes[:tubes_before]
        doc.recompute()
        result["final_state"] = list(guide.State)
        # The event loop keeps running while the kernel works (a timer keeps ticking during a recompute).
        ticks = [0]
        timer = QtCore.QTimer()
        timer.timeout.connect(lambda: ticks.__setitem__(0, ticks[0] + 1))
        timer.start(20)
        start = time.perf_counter()
        guide.Shell.Thickness = guide.Shell.Thickness.Value + 0.3
        doc.recompute()
        result["responsive"] = {"ticks": ticks[0], "seconds": time.perf_counter() - start, "state": list(guide.State)}
        timer.stop()
        # The map goes when the guide is recomputed (it no longer matches the mesh).
        guide.ViewObject.Coloring = True
        guide.ThicknessMap = [(0.5, 0.5, 0.5)] * guide.Mesh.CountFacets
        guide.Tubes[0].Length = guide.Tubes[0].Length.Value + 1.0
        doc.recompute()
        result["map_after_recompute"] = len(guide.ThicknessMap)

        # The replay: every document closed, the recorded lines run as a macro runs them.
        for name in list(App.listDocuments()):
            App.closeDocument(name)
        Gui.updateGui()
        namespace = {"App": App, "FreeCAD": App, "Gui": Gui, "FreeCADGui": Gui}
        exec(compile("\n".join(macro), "recorded-macro.FCMacro", "exec"), namespace)
        replayed = App.getDocument(doc_name)
        result["recorded"], result["replayed"] = recorded, snapshot(replayed)
    except Exception:
        result["errors"].append(traceback.format_exc())
    finally:
        finish(os.path.join(out, "gui-plan-result.json"), result)


QtCore.QTimer.singleShot(500, work)

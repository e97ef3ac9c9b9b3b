"""The Validate task panel: the inspection of a guide or template (stfunctions.inspection) with its verdict,
seating, bores, saw slots' blade paths and labels, removal and stability (score, free motions, where to press, which border to extend), the
thickness map on the mesh with its colour bar and a click reading the distance there, and on demand the undercut map and the contacts. Its form is
Resources/ui/validate.ui."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from sttaskpanels.colour_bar import ColourBar, MapReader
from stfunctions.inspection import inspect
from stutils.gui_utils import load_form


class ValidatePanel:
    """The inspection of a guide or template in a task panel, its thickness map on the mesh."""

    last = None  # the open panel, for scripts and tests

    def __init__(self, obj):
        ValidatePanel.last = self
        self.obj = obj
        self.form = load_form("validate")
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            self.result = inspect(obj)
            self.error = None
        except (ValueError, RuntimeError) as e:
            self.result, self.error = None, str(e)
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        f = self.form
        if self.error:
            App.Console.PrintError(f"Surgical Template: Validate failed: {self.error}\n")
            f.failure.setText(f"Could not inspect {obj.Label}:\n{self.error}")
            f.report.hide()
            return
        f.failure.hide()
        r = self.result
        f.verdict.setText(("PASSED: " if r["passed"] else "FAILED: ") + obj.Label)
        f.verdict.setStyleSheet("font-weight: bold; color: %s" % ("#2a7d3a" if r["passed"] else "#b3261e"))
        solid = r["solid"]
        f.solid.setText(solid["summary"])
        f.volume.setText(f"{solid['volume']:.1f} mm\u00b3, {solid['components']} piece(s)")
        f.seating.setText("nothing in the bone" if r["vertices_in_bone"] == 0 else
                          f"{r['vertices_in_bone']} vertices in the bone, deepest {r['deepest_in_bone']:.3f} mm")
        f.seated.setText(f"{r['seated_vertices']} vertices within 0.01 mm of the clearance ({r['clearance']:.2f} mm)")
        removal = r.get("removal")
        if removal is None:
            f.removal.setText("not checked (the template has no insertion direction)")
        elif removal["removable"]:
            d = removal["direction"]
            f.removal.setText(f"comes off along ({-d[0]:.2f}, {-d[1]:.2f}, {-d[2]:.2f}) over 20 mm")
        else:
            p = removal["blocking"][0]
            f.removal.setText(f"meets the bone near ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) and "
                              f"{len(removal['blocking']) - 1} other place(s): magenta in the map")
        self.show_stability_lines(r.get("stability"))
        if r["bores"]:
            f.bores.setRowCount(len(r["bores"]))
            for i, b in enumerate(r["bores"]):
                for j, text in enumerate((b["name"], f"{b['margin']:.3f}", "yes" if b["open"] else "NO")):
                    f.bores.setItem(i, j, QtGui.QTableWidgetItem(text))
            f.bores.resizeColumnsToContents()
        else:
            f.bores.hide()
        rows = [(p["name"], p["check"], p["result"]) for p in r.get("parts", [])]
        if rows:
            f.parts.setRowCount(len(rows))
            for i, row in enumerate(rows):
                for j, text in enumerate(row):
                    f.parts.setItem(i, j, QtGui.QTableWidgetItem(text))
            f.parts.resizeColumnsToContents()
        else:
            f.parts.hide()
        # The map's colour bar, and a click on the object reading the distance there.
        self.bar = ColourBar(r["thickness"], r["clearance"])
        layout = QtGui.QVBoxLayout(f.legend)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.bar)
        self.reader = MapReader(Gui.ActiveDocument.ActiveView, obj, r["face_distance"], f.reading)
        self.show_map = f.show_map
        self.show_map.toggled.connect(lambda on: setattr(obj.ViewObject, "Coloring", bool(on)))
        # The undercut map on the template (the guide's shell): the bone it covers, hidden parts red.
        shell = getattr(obj, "Shell", None) or obj
        self.overlay = getattr(getattr(shell, "ViewObject", None) and shell.ViewObject.Proxy, "overlay", None)
        self.undercut = getattr(shell.Proxy, "undercut", None)
        self.show_undercuts = f.show_undercuts
        if self.overlay is None or self.undercut is None:
            self.show_undercuts.setEnabled(False)
            self.show_undercuts.setToolTip("The template has no insertion direction (or has not been recomputed)")
        else:
            self.show_undercuts.toggled.connect(lambda on: self.overlay.show_map(*self.undercut, on=bool(on)))
        self.show_stability = f.show_stability
        if self.overlay is None or not r.get("stability"):
            self.show_stability.setEnabled(False)
            self.show_stability.setToolTip("The template has no insertion direction (or has not been recomputed)")
        else:
            self.show_stability.toggled.connect(
                lambda on: self.overlay.show_stability(r["stability"], on=bool(on)))
        (App.Console.PrintMessage if r["passed"] else App.Console.PrintError)(
            f"Surgical Template: {obj.Label}: {r['summary']}\n")

    def show_stability_lines(self, s):
        """The stability rows: score, free motions, where to press, and which border to extend."""
        f = self.form
        if not s:
            f.stability.setText("not analysed (the template has no insertion direction)")
            for w in (f.free_motions, f.press, f.extend, f.label_free_motions, f.label_press, f.label_extend):
                w.hide()
            return
        worst = s["worst_motion"]["text"]
        f.stability.setText(f"score {s['score']:.2f} from {s['contacts']} contacts (0: it can slide or turn, "
                            f"1: it can only lift off); worst: {worst}")
        f.free_motions.setText("\n".join(m["text"] for m in s["free_motions"]) or "none")
        p = s["press_point"]
        f.press.setText(f"near ({p[0]:.2f}, {p[1]:.2f}, {p[2]:.2f}) along the insertion direction "
                        f"(score {s['press_score']:.2f} pressed there)")
        if "extend" in s:
            f.extend.setText(s["extend"]["text"])
        else:
            f.extend.hide()
            f.label_extend.hide()

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        if getattr(self, "reader", None) is not None:
            self.reader.stop()
        if getattr(self, "overlay", None) is not None:
            self.overlay.show_map(None, None, on=False)
            self.overlay.show_stability(None, on=False)
        Gui.Control.closeDialog()
        return True

"""The Validate task panel: the inspection of a guide or template (stfunctions.inspection) with its verdict,
seating and bores, and the thickness map on the mesh with its legend."""
import FreeCAD as App
import FreeCADGui as Gui
from PySide import QtCore, QtGui

from stfunctions.inspection import inspect, thickness_colour


class ValidatePanel:
    """The inspection of a guide or template in a task panel, its thickness map on the mesh."""

    last = None  # the open panel, for scripts and tests

    def __init__(self, obj):
        ValidatePanel.last = self
        self.obj = obj
        self.form = QtGui.QWidget()
        self.form.setWindowTitle("Validate")
        layout = QtGui.QVBoxLayout(self.form)
        QtGui.QApplication.setOverrideCursor(QtCore.Qt.WaitCursor)
        try:
            self.result = inspect(obj)
            self.error = None
        except (ValueError, RuntimeError) as e:
            self.result, self.error = None, str(e)
        finally:
            QtGui.QApplication.restoreOverrideCursor()
        if self.error:
            App.Console.PrintError(f"Surgical Template: Validate failed: {self.error}\n")
            layout.addWidget(QtGui.QLabel(f"Could not inspect {obj.Label}:\n{self.error}"))
            return
        r = self.result
        verdict = QtGui.QLabel(("PASSED: " if r["passed"] else "FAILED: ") + obj.Label)
        verdict.setStyleSheet("font-weight: bold; color: %s" % ("#2a7d3a" if r["passed"] else "#b3261e"))
        layout.addWidget(verdict)
        solid = r["solid"]
        rows = [("Solid", solid["summary"]),
                ("Volume", f"{solid['volume']:.1f} mm\u00b3, {solid['components']} piece(s)"),
                ("Seating", "nothing in the bone" if r["vertices_in_bone"] == 0 else
                 f"{r['vertices_in_bone']} vertices in the bone, deepest {r['deepest_in_bone']:.3f} mm"),
                ("On the bone", f"{r['seated_vertices']} vertices within 0.01 mm of the clearance "
                                f"({r['clearance']:.2f} mm)")]
        form = QtGui.QFormLayout()
        for label, text in rows:
            value = QtGui.QLabel(text)
            value.setWordWrap(True)
            form.addRow(label, value)
        layout.addLayout(form)
        if r["bores"]:
            table = QtGui.QTableWidget(len(r["bores"]), 3)
            table.setHorizontalHeaderLabels(["Tube", "Bore margin (mm)", "Drill passes"])
            for i, b in enumerate(r["bores"]):
                for j, text in enumerate((b["name"], f"{b['margin']:.3f}", "yes" if b["open"] else "NO")):
                    table.setItem(i, j, QtGui.QTableWidgetItem(text))
            table.resizeColumnsToContents()
            layout.addWidget(table)
        layout.addWidget(QtGui.QLabel("Thickness map (distance from the bone):"))
        t, c = r["thickness"], r["clearance"]
        for distance, text in ((-1.0, "in the bone"), (c, f"{c:.2f} mm: seated"),
                               (c + t / 2, f"{c + t / 2:.2f} mm"), (c + t, f"{c + t:.2f} mm: outer surface"),
                               (c + 2 * t, "beyond: sleeves")):
            colour = QtGui.QColor.fromRgbF(*thickness_colour(distance, t, c))
            swatch = QtGui.QLabel(f"  \u25a0  {text}")
            swatch.setStyleSheet(f"color: {colour.name()}")
            layout.addWidget(swatch)
        self.show_map = QtGui.QCheckBox("Show the thickness map")
        self.show_map.setChecked(True)
        self.show_map.toggled.connect(lambda on: setattr(obj.ViewObject, "Coloring", bool(on)))
        layout.addWidget(self.show_map)
        (App.Console.PrintMessage if r["passed"] else App.Console.PrintError)(
            f"Surgical Template: {obj.Label}: {r['summary']}\n")

    def getStandardButtons(self):
        return int(QtGui.QDialogButtonBox.Close)

    def reject(self):
        Gui.Control.closeDialog()
        return True

# Surgical Template workbench, at application start (with or without the GUI). The API is
# `import SurgicalTemplate` (this folder is on sys.path once FreeCAD has scanned its Mod folders).
# File > Open and File > Import read case files and 3D Slicer plans through st_import.
import FreeCAD

FreeCAD.addImportType("Surgical Template case or 3D Slicer plan (*.json)", "st_import")

# Surgical Template workbench: nothing to do at application start without the GUI. The API is
# `import SurgicalTemplate` (this folder is on sys.path once FreeCAD has scanned its Mod folders).

"""Where the workbench is installed (InitGui.py runs without __file__ in FreeCAD 0.20), its icons,
its Qt Designer forms and its drawing templates."""
import os

HERE = os.path.dirname(os.path.abspath(__file__))
ICONS = os.path.join(HERE, "icons")
UI = os.path.join(HERE, "Resources", "ui")
TEMPLATES = os.path.join(HERE, "Resources", "templates")
TRANSLATIONS = os.path.join(HERE, "Resources", "translations")
# The example cases, bones and plans: installed beside the workbench (make install); in a source checkout,
# the repository's examples folder.
EXAMPLES = next((p for p in (os.path.join(HERE, "examples"), os.path.join(HERE, "..", "..", "examples"))
                 if os.path.isdir(os.path.join(p, "cases"))), os.path.join(HERE, "examples"))

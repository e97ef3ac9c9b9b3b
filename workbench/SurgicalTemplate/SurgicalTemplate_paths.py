"""Where the workbench is installed (InitGui.py runs without __file__ in FreeCAD 0.20)."""
import os

HERE = os.path.dirname(os.path.abspath(__file__))

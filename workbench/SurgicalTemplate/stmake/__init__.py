"""The functions that make and change the workbench's objects (the tree, cases, plans, the drawing),
each one undo step; they work headless and attach view providers only when FreeCAD's GUI is up.
SurgicalTemplate.py is their public face."""

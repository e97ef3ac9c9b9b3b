"""Functions on the workbench's objects that make none: the tree an object belongs to (query), the
inspection of a guide or template (inspection), the sleeve catalogue (presets). Headless; the
task panels, the make functions and the commands use them."""

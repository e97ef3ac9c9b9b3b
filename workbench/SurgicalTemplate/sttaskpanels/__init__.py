"""The workbench's task panels (boundary, tube, validate). Every change they make goes through
stutils.gui_utils.run: recorded and undoable."""

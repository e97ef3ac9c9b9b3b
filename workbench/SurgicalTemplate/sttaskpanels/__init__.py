"""The workbench's task panels (boundary, tube, validate), their forms Qt Designer files under
Resources/ui. Every change they make goes through stutils.gui_utils.run: recorded and undoable."""

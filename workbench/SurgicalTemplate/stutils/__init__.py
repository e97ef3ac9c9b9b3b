"""Helpers the workbench's GUI layers share (gui_utils)."""

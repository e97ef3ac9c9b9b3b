"""The view providers of the workbench's objects: icons, children in the tree, edit mode, the context
menu and what follows the data in the 3D view. GUI modules are imported where they are used, so that
documents (which name the view provider class) also open without the GUI."""

"""Alias module for saved documents: FreeCAD stores each proxy as module and class name, and documents
saved before the workbench was split by role name `st_features.Boundary`, `.Template`, `.Tube`,
`.Guide` and `.ViewProvider`. Their homes are now stobjects and stviewproviders."""
from stobjects.boundary import Boundary  # noqa: F401
from stobjects.guide import Guide  # noqa: F401
from stobjects.template import Template  # noqa: F401
from stobjects.tube import Tube  # noqa: F401
from stviewproviders.view_feature import ViewProvider  # noqa: F401

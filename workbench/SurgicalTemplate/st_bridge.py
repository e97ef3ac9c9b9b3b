"""Between FreeCAD and the kernel module (stkernel): the import, and meshes in and out.

Meshes cross as binary STL files in a private temporary folder, the fast path both ways (FreeCAD's
tuple constructor is ten times slower, see the platform notes); facet order is kept, which the guide
relies on (a template's first `InnerFaces` facets are its inner surface).
"""
import os
import shutil
import sys
import tempfile

import FreeCAD as App
import Mesh

_HERE = os.path.dirname(os.path.abspath(__file__))
if _HERE not in sys.path:
    sys.path.insert(0, _HERE)  # stkernel*.so is installed next to this file


def kernel():
    """The kernel module, or an ImportError that says how to get it."""
    try:
        import stkernel
    except ImportError as e:
        raise ImportError("Surgical Template: the kernel module 'stkernel' is not installed next to the "
                          f"workbench ({_HERE}); run `make install` in the project ({e})") from e
    return stkernel


def call(function, *args, **kwargs):
    """function(*args, **kwargs) of the kernel. In the GUI it runs in a worker thread (the kernel
    releases Python's lock while it works) and FreeCAD keeps painting and animating its busy indicator
    meanwhile; user input waits, as during FreeCAD's own long operations. Exceptions come through."""
    if not App.GuiUp:
        return function(*args, **kwargs)
    import threading
    from PySide import QtCore

    outcome = {}

    def work():
        try:
            outcome["value"] = function(*args, **kwargs)
        except BaseException as e:  # noqa: B902 (handed to the caller's thread)
            outcome["error"] = e

    worker = threading.Thread(target=work, name="surgical-template-kernel", daemon=True)
    worker.start()
    while worker.is_alive():
        QtCore.QCoreApplication.processEvents(QtCore.QEventLoop.ExcludeUserInputEvents, 30)
        worker.join(0.01)
    if "error" in outcome:
        raise outcome["error"]
    return outcome["value"]


class _Scratch:
    def __enter__(self):
        self.path = tempfile.mkdtemp(prefix="surgical-template-")
        return self.path

    def __exit__(self, *exc):
        shutil.rmtree(self.path, ignore_errors=True)


def read_mesh_file(path):
    """(vertices, triangles) of an STL/PLY/OBJ file, also .gz, with the kernel's reader."""
    return kernel().read_mesh(path)


def mesh_to_arrays(mesh):
    """(vertices, triangles) of a FreeCAD Mesh, facets in FreeCAD's order."""
    with _Scratch() as d:
        path = os.path.join(d, "mesh.stl")
        mesh.write(path)
        return kernel().read_mesh(path)


def arrays_to_mesh(vertices, triangles):
    """A FreeCAD Mesh from (vertices, triangles), facets in the same order."""
    with _Scratch() as d:
        path = os.path.join(d, "mesh.stl")
        kernel().write_stl(vertices, triangles, path)
        mesh = Mesh.Mesh(path)
    if mesh.CountFacets != len(triangles):
        raise RuntimeError(f"FreeCAD changed the mesh on reading it ({len(triangles)} -> {mesh.CountFacets} facets)")
    return mesh


_bone_cache = {}


def bone_arrays(bone):
    """(vertices, triangles) of a bone Mesh feature, converted once per mesh state."""
    m = bone.Mesh
    key = (bone.Document.Name, bone.Name, m.CountPoints, m.CountFacets, round(m.Area, 6), str(m.BoundBox))
    if key not in _bone_cache:
        if len(_bone_cache) > 8:
            _bone_cache.clear()
        _bone_cache[key] = mesh_to_arrays(m)
    return _bone_cache[key]


def vec(v):
    return [float(v.x), float(v.y), float(v.z)]


def report(message):
    App.Console.PrintMessage(f"Surgical Template: {message}\n")

"""Designs a template from a case file inside FreeCAD (GUI or freecadcmd) with the kernel module.

In FreeCAD's Python console or as a macro (set ST_CASE and, if the module is not installed, ST_PYTHON
to the folder holding stkernel*.so, e.g. build/python):

    ST_CASE=examples/cases/vertebra-pedicle.json ST_PYTHON=build/python freecadcmd examples/macros/design_in_freecad.py

It adds the bone and the template (with its drilling sleeves) as Mesh features to a new document, reports the check in the
Report view / console and, with ST_FCSTD set, saves the document there.
"""
import os
import sys

import FreeCAD as App
import Mesh

if os.environ.get("ST_PYTHON"):
    sys.path.insert(0, os.environ["ST_PYTHON"])
import stkernel  # noqa: E402


def mesh_feature(doc, name, vertices, triangles):
    """A Mesh::Feature from numpy arrays (facets given as point triples)."""
    facets = [[tuple(vertices[i]) for i in tri] for tri in triangles]
    obj = doc.addObject("Mesh::Feature", name)
    obj.Mesh = Mesh.Mesh(facets)
    return obj


def design(case_path, fcstd=None):
    case = stkernel.read_case(case_path)
    V, F = stkernel.read_mesh(case["bone"])
    r = stkernel.design_template(V, F, case["boundary_points"], thickness=case["thickness"],
                                 clearance=case["clearance"], resolution=case["resolution"] or 0.0,
                                 sampling_step=case["sampling_step"] or 0, inside=case["inside"],
                                 tubes=case["tubes"])
    doc = App.newDocument(case["name"].replace("-", "_"))
    mesh_feature(doc, "Bone", V, F)
    tpl = mesh_feature(doc, "Template", *r["shell"])
    doc.recompute()
    App.Console.PrintMessage(f"{case['name']}: {r['solid']['summary']}\n")
    if fcstd:
        doc.saveAs(fcstd)
    return doc, tpl, r


if __name__ == "__main__" or os.environ.get("ST_CASE"):
    design(os.environ["ST_CASE"], os.environ.get("ST_FCSTD"))

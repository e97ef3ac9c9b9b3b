"""A template or guide written for printing (3MF, STL, OBJ, ...) or its sleeves for CAD (STEP, IGES,
BREP), each file written whole or not at all."""
import os
import zipfile
from xml.sax.saxutils import escape

import Part

import st_bridge

MESH_FORMATS = (".3mf", ".stl", ".obj", ".ply", ".amf", ".off")
SOLID_FORMATS = (".step", ".stp", ".iges", ".igs", ".brep")


def export(obj, path):
    """Writes a template or guide, the format by the extension: its mesh as 3MF (what printers prefer: the
    units, mm, are in the file; write_3mf), STL (binary, the kernel's writer), OBJ, PLY, AMF or OFF
    (FreeCAD's mesh writer); or a guide's sleeves as the exact OpenCASCADE solids of its tubes in STEP, IGES or BREP, for
    CAD. Written whole or not at all; returns the path."""
    path = os.fspath(path)
    ext = os.path.splitext(path)[1].lower()
    if ext in SOLID_FORMATS:
        tubes = list(getattr(obj, "Tubes", []))
        if not tubes:
            raise ValueError(f"{obj.Label}: no sleeves to write as {ext[1:].upper()} (only a guide's tubes are solids)")
        return _replace_whole(path, lambda tmp: Part.export(tubes, tmp))
    if ext not in MESH_FORMATS:
        raise ValueError(f"{path}: unknown format '{ext[1:]}'; write one of "
                         f"{', '.join(e[1:] for e in MESH_FORMATS + SOLID_FORMATS)}")
    if not hasattr(obj, "Mesh"):
        raise ValueError(f"{obj.Label}: not a mesh object")
    if obj.Mesh.CountFacets == 0:
        raise ValueError(f"{obj.Label}: the mesh is empty (recompute it first)")
    if ext == ".stl":
        st_bridge.kernel().write_stl(*st_bridge.mesh_to_arrays(obj.Mesh), path)
        return path
    if ext == ".3mf":
        V, F = st_bridge.mesh_to_arrays(obj.Mesh)
        return _replace_whole(path, lambda tmp: write_3mf(tmp, V, F, obj.Label))
    return _replace_whole(path, obj.Mesh.write)


def _replace_whole(path, write):
    """Calls write(temporary path with the same extension, beside `path`), then puts it in place: a
    failure leaves what was there before."""
    folder, name = os.path.split(os.path.abspath(path))
    tmp = os.path.join(folder, f".{name}.part{os.path.splitext(name)[1]}")
    try:
        write(tmp)
        if not os.path.exists(tmp) or os.path.getsize(tmp) == 0:
            raise RuntimeError(f"{path}: nothing was written")
        os.replace(tmp, path)
    finally:
        if os.path.exists(tmp):
            os.remove(tmp)
    return path


_CONTENT_TYPES = ('<?xml version="1.0" encoding="UTF-8"?>\n'
                  '<Types xmlns="http://schemas.openxmlformats.org/package/2006/content-types">'
                  '<Default Extension="rels" '
                  'ContentType="application/vnd.openxmlformats-package.relationships+xml"/>'
                  '<Default Extension="model" ContentType="application/vnd.ms-package.3dmanufacturing-3dmodel+xml"/>'
                  '</Types>\n')
_RELS = ('<?xml version="1.0" encoding="UTF-8"?>\n'
         '<Relationships xmlns="http://schemas.openxmlformats.org/package/2006/relationships">'
         '<Relationship Target="/3D/3dmodel.model" Id="rel0" '
         'Type="http://schemas.microsoft.com/3dmanufacturing/2013/01/3dmodel"/></Relationships>\n')


def write_3mf(path, V, F, name):
    """A 3MF package (3MF core specification 1.x) of one mesh object in millimetres. Coordinates keep the
    mesh's float values exactly (9 significant digits): FreeCAD 0.20's own 3MF writer keeps 6, which
    moves vertices by up to 0.0005 mm at 600 mm from the origin, enough to cross the finest features."""
    lines = ['<?xml version="1.0" encoding="UTF-8"?>',
             '<model unit="millimeter" xml:lang="en-US" '
             'xmlns="http://schemas.microsoft.com/3dmanufacturing/core/2015/02">',
             '<metadata name="Application">Surgical Template (FreeCAD)</metadata>',
             f'<metadata name="Title">{escape(name)}</metadata>',
             f'<resources><object id="1" type="model" name="{escape(name, {chr(34): "&quot;"})}"><mesh><vertices>']
    lines += [f'<vertex x="{x:.9g}" y="{y:.9g}" z="{z:.9g}"/>' for x, y, z in V.tolist()]
    lines.append("</vertices><triangles>")
    lines += [f'<triangle v1="{a}" v2="{b}" v3="{c}"/>' for a, b, c in F.tolist()]
    lines.append('</triangles></mesh></object></resources><build><item objectid="1"/></build></model>')
    with zipfile.ZipFile(path, "w", zipfile.ZIP_DEFLATED) as z:
        z.writestr("[Content_Types].xml", _CONTENT_TYPES)
        z.writestr("_rels/.rels", _RELS)
        z.writestr("3D/3dmodel.model", "\n".join(lines) + "\n")

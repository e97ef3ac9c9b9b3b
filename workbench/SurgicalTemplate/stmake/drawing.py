"""make_drawing: the documentation drawing of a guide, its TechDraw page in the document (stdrawing.page)
exported to PDF and SVG (stdrawing.export), with the drill protocol next to them (stdrawing.protocol).

    import SurgicalTemplate as st
    guide = st.load_case("examples/cases/maxilla-implants.json")
    st.make_drawing(guide, "out/maxilla.pdf")   # out/maxilla.pdf, .svg, .txt; returns the page and protocol
"""
import datetime
import os

import st_bridge
from stdrawing import export
from stdrawing.page import Builder, check_page, paper_spec, remove_drawings_of
from stdrawing.protocol import drill_protocol
from stobjects.base import kind_of


def _check_guide(guide):
    label = getattr(guide, "Label", repr(guide))
    if kind_of(guide) != "Guide":
        raise ValueError(f"{label}: not a surgical guide")
    doc = guide.Document
    if any("Touched" in o.State for o in [guide, guide.Shell, *guide.Tubes] if o is not None):
        doc.recompute()
    if "Invalid" in guide.State:
        why = getattr(guide, "Status", "") or "see the Report view"
        raise ValueError(f"{label}: the guide failed to recompute ({why})")
    if guide.Shell is None:
        raise ValueError(f"{label}: the guide has no template shell")
    if guide.Mesh.CountFacets == 0:
        raise ValueError(f"{label}: the guide mesh is empty (recompute it first)")
    for tube in guide.Tubes:
        if tube.Shape.isNull() or not tube.Shape.Solids:
            raise ValueError(f"{tube.Label}: the tube has no solid (recompute it first)")


def make_drawing(guide, path, paper="A3", pdf=True, svg=True):
    """The documentation drawing of a guide: a TechDraw page in its document (one undo step, replacing
    the guide's previous drawing) with front, top and side views, a dimensioned detail per sleeve and per
    saw slot and tables of the sleeves, the slots and the template; exported to PDF and SVG at `path` with its extension
    replaced, and a drill protocol next to them (.txt). Without the GUI the export runs FreeCAD under
    Xvfb in a subprocess. Returns {"page", "pdf", "svg", "protocol" (the text), "protocol_path"}."""
    _check_guide(guide)
    spec = paper_spec(paper)
    doc = guide.Document
    base = os.path.splitext(os.path.abspath(os.fspath(path)))[0]
    folder = os.path.dirname(base)
    os.makedirs(folder, exist_ok=True)
    date = datetime.datetime.now().strftime("%Y-%m-%d %H:%M")
    protocol = drill_protocol(guide, date)
    builder = Builder(doc, guide, spec, date)
    builder.arrays = st_bridge.mesh_to_arrays(guide.Mesh)
    doc.openTransaction("Make drawing")
    try:
        page = builder.build()
        doc.recompute()
        builder.dimension_details()
        doc.recompute()
        check_page(builder)
        remove_drawings_of(guide, keep=page)  # only now: a failure above keeps the old drawing
        doc.commitTransaction()
    except Exception:
        doc.abortTransaction()
        builder.remove_created()
        raise
    out = {"page": page, "pdf": None, "svg": None, "protocol": protocol, "protocol_path": base + ".txt"}
    targets = {k: base + "." + k for k, wanted in (("pdf", pdf), ("svg", svg)) if wanted}
    out.update(export.write_page(page, targets))
    export.write_text(base + ".txt", protocol)
    return out

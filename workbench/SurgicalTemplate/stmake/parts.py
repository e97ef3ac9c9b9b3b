"""What a cutting guide carries besides its tubes: saw slots and labels, Slot and Label objects in the
guide's Parts (stobjects.parts), made from the case file's keys. Adding one recomputes the guide; when the kernel refuses
it (off the template, too close to a sleeve, blade path blocked, ...), the guide is left as it was and
the kernel's message is raised, naming the part and the place.

    import SurgicalTemplate as st
    st.add_label(guide, at=(621, 412, 350), up=(0, 0, 1))              # text: the case's name
    st.add_slot(guide, origin=(617, 411.9, 385), normal=(0, 0, 1), direction=(0, 1, 0), blade=0.89, length=16)
"""
import numpy as np

from stmake.objects import make_label, make_slot
from stmake.step import Step
from stobjects.guide import Guide


def _plain(v):
    return [float(c) for c in (v.x, v.y, v.z)] if hasattr(v, "x") else [float(c) for c in np.asarray(v, float)]


def _unique(names, stem):
    k = len(names) + 1
    while f"{stem} {k}" in names:
        k += 1
    return f"{stem} {k}"


def _add(guide, make, item, title):
    """Adds a part (make_slot, make_label) to the guide and recomputes; on refusal removes it again."""
    if getattr(guide, "Proxy", None) is None or not isinstance(guide.Proxy, Guide):
        raise ValueError(f"{getattr(guide, 'Label', guide)}: not a surgical guide")
    doc = guide.Document
    with Step(doc, title):
        obj = make(guide, item)
        doc.recompute()
        if "Invalid" in guide.State or "Error" in guide.State:
            status = guide.Status if guide.Status.startswith("failed: ") else ""
            guide.Parts = [p for p in guide.Parts if p != obj]
            doc.removeObject(obj.Name)
            doc.recompute()
            raise RuntimeError(f"{title} on {guide.Label} failed: {status[len('failed: '):] or 'the kernel refused it'}")
    return dict(item, name=obj.Label)


def add_label(guide, at, up, text=None, height=4.0, depth=0.6, mode="engrave", name=None):
    """Adds a label to the guide (a Label object in its Parts): `text` (default: the case's name, the
    guide's label) centred near `at` on the outer surface, reading with `up` up; cap height and depth in
    mm; mode "engrave" or "emboss". One undo step. Returns the label's dict (the case file's keys)."""
    labels = Guide.labels_of(guide)
    item = {"name": name or _unique({l.get("name") for l in labels}, "label"),
            "text": text if text is not None else guide.Label, "at": _plain(at), "up": _plain(up),
            "height": float(height), "depth": float(depth), "mode": mode}
    return _add(guide, make_label, item, "Add label")


def add_slot(guide, origin, normal, direction, blade, length, clearance=0.1, height=5.0, wall=3.0,
             closed=("start", "end"), name=None):
    """Adds a saw slot to the guide (a Slot object in its Parts): the cut plane through `origin` with
    `normal`, the saw travelling along `direction` (into the bone), a blade `blade` mm thick with
    `clearance` on each side, `length` mm across, its housing `height` over the template with walls `wall`
    thick, `closed` ends. One undo step. Returns the slot's dict (the case file's keys)."""
    slots = Guide.slots_of(guide)
    item = {"name": name or _unique({s.get("name") for s in slots}, "slot"), "origin": _plain(origin),
            "normal": _plain(normal), "direction": _plain(direction), "blade": float(blade),
            "clearance": float(clearance), "length": float(length), "height": float(height), "wall": float(wall),
            "closed": list(closed)}
    return _add(guide, make_slot, item, "Add saw slot")

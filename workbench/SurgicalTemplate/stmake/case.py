"""Case files (docs/CASE-FORMAT.md) in and out."""
import os

import FreeCAD as App

import st_bridge
from stmake.objects import make_bone, make_boundary, make_guide, make_template, make_tube, view_of
from stmake.step import Step
from stobjects.case_info import FIELDS, FRAMES, STATUSES, CaseInfo, case_info_of
from stobjects.template import insertion_argument


def _direction(tube, case):
    """The tube's direction; a pin planned by its entry only gets the one the kernel would give it."""
    if tube["direction"] is not None:
        return tube["direction"]
    k = st_bridge.kernel()
    v, f = k.read_mesh(case["bone"])
    return k.pin_direction(v, f, tube["entry"], tube["outer_radius"], tube["name"])


def load_case(path, doc=None):
    """Builds the whole parametric tree of a case file (docs/CASE-FORMAT.md) and returns the guide."""
    case = st_bridge.kernel().read_case(path)
    doc = doc or App.newDocument(case["name"].replace("-", "_") or "SurgicalTemplate")
    with Step(doc, "Open case"):
        bone = make_bone(case["bone"], doc)
        boundary = make_boundary(bone, case["boundary_points"], case["inside"])
        shell = make_template(boundary, case["thickness"], case["clearance"], case["resolution"] or 0.0,
                              case["sampling_step"] or 0, insertion=case.get("insertion"))
        tubes = [make_tube(t["entry"], _direction(t, case), t["inner_radius"], t["outer_radius"], t["length"],
                           t["offset"], name=t["name"], doc=doc, depth=t["depth"], kind=t.get("kind"),
                           counterbore=t.get("counterbore")) for t in case["tubes"]]
        guide = make_guide(shell, tubes, slots=case.get("slots", []), labels=case.get("labels", []))
        guide.Label = case["name"] or "SurgicalGuide"
        set_case_info(guide, CaseId=case["name"])
    doc.recompute()
    return guide


def save_case(guide, path, output=None):
    """Writes the guide's plan as a case file, so that load_case(save_case(g)) rebuilds it."""
    shell = guide.Shell
    boundary = shell.Boundary
    bone = boundary.Bone
    source = getattr(bone, "SourceFile", "")
    if not source:
        raise ValueError(f"{bone.Label}: the bone was not read from a file; export it first")
    st_bridge.kernel().write_case({
        "name": guide.Label,
        "bone": source,
        "boundary_points": [st_bridge.vec(p) for p in boundary.Points],
        "inside": st_bridge.vec(boundary.Inside) if boundary.UseInside else None,
        "thickness": float(shell.Thickness.Value),
        "clearance": float(shell.Clearance.Value),
        "resolution": float(shell.Resolution.Value) if shell.Resolution.Value > 0 else None,
        "sampling_step": int(shell.SamplingStep) if shell.SamplingStep > 0 else None,
        "insertion": insertion_argument(shell),
        "tubes": [t.Proxy.spec(t) for t in guide.Tubes],
        "slots": guide.Proxy.slots_of(guide),
        "labels": guide.Proxy.labels_of(guide),
        "output": os.path.join(os.path.dirname(os.path.abspath(path)), output) if output else None,
    }, path)
    return path


def set_case_info(guide, **fields):
    """The case's document data for `guide` (its CaseInfo object, made when it has none), with `fields`
    set: Owner, DocumentType, DesignedBy, CheckedBy, ApprovedBy, CaseId, Surgeon, ImplantSystem,
    Material, PrintingProcess, Revision (text), Status (one of STATUSES) and PatientFrame ("LPS" or "RAS":
    the bone's coordinates in that patient frame, so that the drawing names its views anatomically). The
    drawing's title block shows them. One undo step; returns the object."""
    known = {name for name, _, _, _ in FIELDS} | {"Status", "PatientFrame"}
    unknown = sorted(set(fields) - known)
    if unknown:
        raise ValueError(f"{guide.Label}: no case field {', '.join(unknown)}; the fields are "
                         f"{', '.join(sorted(known))}")
    if "Status" in fields and fields["Status"] not in STATUSES:
        raise ValueError(f"{guide.Label}: status {fields['Status']!r}: use one of {', '.join(STATUSES)}")
    if "PatientFrame" in fields and fields["PatientFrame"] not in FRAMES:
        raise ValueError(f"{guide.Label}: patient frame {fields['PatientFrame']!r}: use one of {', '.join(FRAMES)}")
    doc = guide.Document
    with Step(doc, "Case data"):
        info = case_info_of(guide)
        if info is None:
            info = doc.addObject("App::FeaturePython", "CaseInfo")
            CaseInfo(info)
            info.Guide = guide
            info.Label = f"{guide.Label} case data"
            view_of(info, "SurgicalTemplate_CaseInfo.svg")
        for name, value in fields.items():
            setattr(info, name, str(value))
    return info

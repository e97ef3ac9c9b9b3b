"""The case's document data (App::FeaturePython): who owns, made, checked and approved the guide's
documentation, its type, status and revision, the case id, the surgeon, the implant system, the material
and the printing process. The drawing's title block is filled from it (stdrawing.page), one field per
property, so that a change here and a new drawing are all it takes to reissue the page. It links to
its guide (Guide), not the guide to it: editing these data recomputes nothing else."""
import FreeCAD as App

from stobjects.base import Feature

# ISO 7200's document statuses, in the order a document goes through them.
STATUSES = ["In preparation", "In approval", "Released", "Withdrawn"]

# The patient frame of the bone's coordinates, when the user states it: the drawing then names its views
# anatomically. Per frame, the side of the patient each axis points to.
FRAMES = ["Not given", "LPS", "RAS"]
SIDES = {"LPS": ("LEFT", "POSTERIOR", "SUPERIOR"), "RAS": ("RIGHT", "ANTERIOR", "SUPERIOR")}
OPPOSITE = {"LEFT": "RIGHT", "RIGHT": "LEFT", "POSTERIOR": "ANTERIOR", "ANTERIOR": "POSTERIOR",
            "SUPERIOR": "INFERIOR", "INFERIOR": "SUPERIOR"}


def viewer_side(frame, towards_viewer):
    """The patient's side a view is seen from ("ANTERIOR", ...) in a frame (LPS, RAS), for a view whose
    direction towards the viewer is an axis (+-X, +-Y, +-Z); None when the frame is not given."""
    if frame not in SIDES:
        return None
    k = max(range(3), key=lambda i: abs(towards_viewer[i]))
    side = SIDES[frame][k]
    return side if towards_viewer[k] > 0 else OPPOSITE[side]

# (property, title-block caption, tooltip, default); the order of the fields in the title block.
FIELDS = (
    ("Owner", "Legal owner", "The hospital, lab or company that owns the document", ""),
    ("DocumentType", "Document type", "What the document is", "Surgical guide drawing"),
    ("DesignedBy", "Designed by", "Who designed the guide (FreeCAD's author name by default)", None),
    ("CheckedBy", "Checked by", "Who checked the design", ""),
    ("ApprovedBy", "Approved by", "Who released it for manufacture", ""),
    ("CaseId", "Case", "The case or patient-pseudonym identifier", ""),
    ("Surgeon", "Surgeon", "The surgeon who planned the case", ""),
    ("ImplantSystem", "Implant system", "Implants, screws or saw system the sleeves and slots are sized for", ""),
    ("Material", "Material", "The printing material (a biocompatible resin for guides used in surgery)", ""),
    ("PrintingProcess", "Printing process", "Printer and process (SLA, DLP, SLS, ...)", ""),
    ("Revision", "Rev.", "Revision index of the document", "A"),
)


def case_info_of(guide):
    """The CaseInfo object documenting `guide`, or None."""
    for o in guide.Document.Objects:
        if getattr(getattr(o, "Proxy", None), "kind", "") == "CaseInfo" and o.Guide == guide:
            return o
    return None


def author_name():
    """FreeCAD's author name (Preferences > General > Document > Author name), or ''."""
    return App.ParamGet("User parameter:BaseApp/Preferences/Document").GetString("prefAuthor", "")


class CaseInfo(Feature):
    kind = "CaseInfo"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyLink", "Guide", "Case", "The guide these data document")
        for name, _, tip, default in FIELDS:
            self.add(obj, "App::PropertyString", name, "Document", tip,
                     author_name() if default is None else default)
        obj.addProperty("App::PropertyEnumeration", "Status", "Document", "Document status (ISO 7200)")
        obj.Status = STATUSES
        obj.Status = STATUSES[0]
        obj.addProperty("App::PropertyEnumeration", "PatientFrame", "Anatomy",
                        "The patient frame of the bone's coordinates (LPS: 3D Slicer and DICOM; RAS), when known: "
                        "the drawing then names its views anatomically (anterior, superior, ...)")
        obj.PatientFrame = FRAMES
        obj.PatientFrame = FRAMES[0]

    def execute(self, obj):
        pass

    @staticmethod
    def fields(obj):
        """{property: text} of every title-block field, Status included."""
        values = {name: str(getattr(obj, name, "")) for name, _, _, _ in FIELDS}
        values["Status"] = str(obj.Status)
        return values

    @staticmethod
    def frame(obj):
        return str(getattr(obj, "PatientFrame", FRAMES[0]))

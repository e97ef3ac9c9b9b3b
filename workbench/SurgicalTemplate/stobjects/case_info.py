"""The case's document data (App::FeaturePython): who owns, made, checked and approved the guide's
documentation, its type, status and revision, the case id, the surgeon, the implant system, the material
and the printing process. The drawing's title block is filled from it (stdrawing.page), one field per
property, so that a change here and a new drawing are all it takes to reissue the page. It links to
its guide (Guide), not the guide to it: editing these data recomputes nothing else."""
import FreeCAD as App

from stobjects.base import Feature

# ISO 7200's document statuses, in the order a document goes through them.
STATUSES = ["In preparation", "In approval", "Released", "Withdrawn"]

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

    def execute(self, obj):
        pass

    @staticmethod
    def fields(obj):
        """{property: text} of every title-block field, Status included."""
        values = {name: str(getattr(obj, name, "")) for name, _, _, _ in FIELDS}
        values["Status"] = str(obj.Status)
        return values

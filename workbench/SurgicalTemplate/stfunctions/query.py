"""Finding the parametric tree (guide, template, boundary, bone) an object belongs to."""
from stobjects.base import kind_of


def tree_of(obj):
    """(guide, template, boundary, bone) built on `obj` (any of them), the latest of each where a bone
    or boundary carries several; None for what does not exist yet."""
    kind = kind_of(obj)
    guide = obj if kind == "Guide" else None
    shell = obj if kind == "Template" else guide.Shell if guide else None
    boundary = obj if kind == "Boundary" else shell.Boundary if shell else None
    bone = obj if kind == "Bone" else boundary.Bone if boundary else None
    objects = obj.Document.Objects
    if boundary is None:
        boundaries = [o for o in objects if kind_of(o) == "Boundary" and o.Bone == bone]
        boundary = boundaries[-1] if boundaries else None
    if shell is None and boundary is not None:
        shells = [o for o in objects if kind_of(o) == "Template" and o.Boundary == boundary]
        shell = shells[-1] if shells else None
    if guide is None and shell is not None:
        guides = [o for o in objects if kind_of(o) == "Guide" and o.Shell == shell]
        guide = guides[-1] if guides else None
    return guide, shell, boundary, bone


def find_guide(obj):
    """The guide built on `obj` (a guide, template, boundary or bone), or None."""
    return tree_of(obj)[0] if obj is not None else None

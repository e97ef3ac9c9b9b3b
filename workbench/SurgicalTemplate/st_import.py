"""File > Open and File > Import of the workbench's files (registered in Init.py): a case file builds its
whole parametric tree (SurgicalTemplate.load_case), a 3D Slicer markups plan goes on the guide or bone of
the document it is imported into (SurgicalTemplate.load_plan). FreeCAD calls open(path) for File > Open
and insert(path, document name) for File > Import."""
import builtins
import json

import FreeCAD as App


def _kind(path):
    """'case' or 'plan' by the file's content; ValueError naming the file for anything else."""
    try:
        with builtins.open(path, encoding="utf-8") as f:  # this module's open is FreeCAD's importer
            doc = json.load(f)
    except (OSError, ValueError) as e:
        raise ValueError(f"{path}: not a readable JSON file: {e}") from None
    if isinstance(doc, dict) and "format" in doc:
        return "case"
    if isinstance(doc, dict) and "markups" in doc:
        return "plan"
    raise ValueError(f"{path}: neither a Surgical Template case (\"format\") nor a 3D Slicer markups plan "
                     "(\"markups\")")


def _report(call):
    """Runs an import; a failure is reported on the console (FreeCAD's importers do not raise to the GUI)
    and raised again for scripts."""
    try:
        return call()
    except (ValueError, RuntimeError) as e:
        App.Console.PrintError(f"Surgical Template: {e}\n")
        raise


def open(path):  # noqa: A001  (FreeCAD's importer interface)
    """File > Open: a case in a new document of its own; a plan needs a bone, so it opens only into a
    document that has one (File > Import)."""
    import SurgicalTemplate as st

    def work():
        if _kind(path) == "plan":
            raise ValueError(f"{path}: a 3D Slicer plan goes on a bone; open its case, or import the bone and "
                             "then File > Import the plan")
        return st.load_case(path)
    return _report(work)


def insert(path, docname):
    """File > Import into the document `docname`: a case builds its tree there, a plan goes on its guide
    (or its bone)."""
    import SurgicalTemplate as st

    def work():
        doc = App.getDocument(docname)
        if _kind(path) == "case":
            return st.load_case(path, doc)
        App.setActiveDocument(doc.Name)
        # Cut planes without a blade or length take the preferences' (as Import plan does).
        from stfunctions.presets import preferred_slot
        blade, length = preferred_slot()
        return st.load_plan(path, blade=blade, slot_length=length)
    return _report(work)

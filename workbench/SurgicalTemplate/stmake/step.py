"""One undo step around a change of a document, and the document a change goes to."""
import FreeCAD as App


def document(doc):
    """`doc`, else the active document, else a new one."""
    return doc or App.ActiveDocument or App.newDocument("SurgicalTemplate")


class Step:
    """One undo step around a change of the document; steps inside a step belong to the outer one.
    On failure the step is undone; where the document keeps no undo (UndoMode 0, as in freecadcmd)
    the objects it made are removed, so nothing half-made stays."""

    _open = set()  # documents with a step under way

    def __init__(self, doc, title):
        self.doc, self.title = doc, title
        self.outer = False

    def __enter__(self):
        if self.doc.Name not in Step._open:
            Step._open.add(self.doc.Name)
            self.outer = True
            self.before = {o.Name for o in self.doc.Objects}
            self.doc.openTransaction(self.title)
        return self

    def __exit__(self, kind, value, tb):
        if self.outer:
            Step._open.discard(self.doc.Name)
            if kind is None:
                self.doc.commitTransaction()
            else:
                self.doc.abortTransaction()
                for name in [o.Name for o in self.doc.Objects if o.Name not in self.before][::-1]:
                    if self.doc.getObject(name) is not None:
                        self.doc.removeObject(name)
        return False

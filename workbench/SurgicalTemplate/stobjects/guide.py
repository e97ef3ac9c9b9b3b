"""The surgical guide (Mesh::FeaturePython): the template shell with its tubes merged and their bores
cut by the kernel, its saw slots cut in their housings and its labels engraved or embossed (its Parts:
Slot and Label objects, since 0.4; documents of 0.3 keep them as the case file's keys in JSON, Slots and
Labels), checked as a
printable solid (how they were placed kept in PartsReport, for Validate); StabilityScore repeats its template's for expressions.
A recompute marks the guide's drawings out of date."""
import json

import numpy as np

import st_bridge
from stobjects.base import Feature


class Guide(Feature):
    kind = "Guide"

    def __init__(self, obj):
        super().__init__(obj)
        self.add(obj, "App::PropertyLink", "Shell", "Guide", "The template shell")
        self.add(obj, "App::PropertyLinkList", "Tubes", "Guide", "The drilling tubes merged into the shell")
        self.add(obj, "App::PropertyLength", "Tolerance", "Guide", "Chordal tolerance of sleeves and bores", 0.01)
        self.add(obj, "App::PropertyFloat", "StabilityScore", "Result",
                 "The template's stability score (0..1): how firmly the guide is held pressed along its "
                 "insertion direction", 0.0, readonly=True)
        self.add(obj, "App::PropertyString", "Status", "Result", "What the kernel reported", "", readonly=True)
        self.properties_since_0_3(obj)

    def properties_since_0_3(self, obj):
        self.add(obj, "App::PropertyString", "Slots", "Guide",
                 "Saw slots cut in their housings: a JSON list with the case file's slot keys "
                 "(docs/CASE-FORMAT.md); empty: none", "")
        self.add(obj, "App::PropertyString", "Labels", "Guide",
                 "Text engraved into or embossed onto the outer surface: a JSON list with the case file's "
                 "label keys (text, at, up, height, depth, mode; docs/CASE-FORMAT.md); empty: none", "")
        self.add(obj, "App::PropertyString", "PartsReport", "Result",
                 "How the kernel placed the slots and labels at the last recompute (its report's slots and "
                 "labels, JSON), for Validate", "", hidden=True)
        self.properties_since_0_4(obj)

    def properties_since_0_4(self, obj):
        self.add(obj, "App::PropertyLinkList", "Parts", "Guide",
                 "Its saw slots and labels (Slot and Label objects); Slots and Labels hold those of documents "
                 "made before 0.4")

    def onDocumentRestored(self, obj):
        super().onDocumentRestored(obj)
        self.properties_since_0_3(obj)

    @staticmethod
    def list_text(items):
        """The text of a JSON list property (Slots, Labels) for dicts of case-file keys (numpy arrays as
        lists)."""
        def plain(v):
            return v.tolist() if isinstance(v, np.ndarray) else v
        return json.dumps([{k: plain(v) for k, v in s.items()} for s in items]) if items else ""

    @staticmethod
    def list_of(obj, prop):
        """The dicts of a JSON list property (Slots, Labels); ValueError naming the guide for text that is
        not them."""
        text = getattr(obj, prop, "")
        if not text.strip():
            return []
        try:
            items = json.loads(text)
        except ValueError as e:
            raise ValueError(f"{obj.Label}: {prop} is not JSON: {e}") from None
        if not isinstance(items, list) or not all(isinstance(i, dict) for i in items):
            raise ValueError(f"{obj.Label}: {prop} must be a JSON list of objects with the case file's keys")
        return items

    @staticmethod
    def parts_of(obj, kind):
        """The guide's Slot or Label objects."""
        return [p for p in getattr(obj, "Parts", []) if getattr(getattr(p, "Proxy", None), "kind", "") == kind]

    @staticmethod
    def slots_of(obj):
        """The guide's slot dicts (case file keys): its Slot objects' and those kept as JSON."""
        return Guide.list_of(obj, "Slots") + [p.Proxy.spec(p) for p in Guide.parts_of(obj, "Slot")]

    @staticmethod
    def labels_of(obj):
        """The guide's label dicts (case file keys): its Label objects' and those kept as JSON."""
        return Guide.list_of(obj, "Labels") + [p.Proxy.spec(p) for p in Guide.parts_of(obj, "Label")]

    @staticmethod
    def placed_of(obj):
        """How the kernel placed the guide's slots and labels at its last recompute: ({slot name: the
        report's slot entry}, [the report's label entries]); empty before a recompute."""
        placed = json.loads(getattr(obj, "PartsReport", "") or "{}")
        return {p["name"]: p for p in placed.get("slots", [])}, placed.get("labels", [])

    def execute(self, obj):
        shell = obj.Shell
        if shell is None or shell.Boundary is None or shell.Boundary.Bone is None:
            raise ValueError(f"{obj.Label}: no template shell on a bone")
        k = st_bridge.kernel()
        V, F = st_bridge.mesh_to_arrays(shell.Mesh)
        if len(F) < shell.InnerFaces or shell.InnerFaces <= 0:
            raise ValueError(f"{obj.Label}: the shell '{shell.Label}' has not been designed yet")
        BV, BF = st_bridge.bone_arrays(shell.Boundary.Bone)
        tubes = [t.Proxy.spec(t) for t in obj.Tubes]
        slots = self.slots_of(obj)
        labels = self.labels_of(obj)
        if tubes or slots or labels:
            try:
                g = st_bridge.call(k.add_tubes, V, F, int(shell.InnerFaces), BV, BF, tubes,
                                   chordal_tolerance=float(obj.Tolerance.Value),
                                   clearance=float(shell.Clearance.Value), slots=slots, labels=labels,
                                   thickness=float(shell.Thickness.Value))
            except Exception as e:  # the kernel's message names the part and the place
                obj.Status = f"failed: {e}"
                raise
            V, F = g["mesh"]
            seconds = g["seconds"]
            placed = {"slots": g["slots"], "labels": g["labels"]}
        else:
            seconds, placed = 0.0, {}
        report = st_bridge.call(k.check_solid, V, F)
        if not report["valid"]:
            raise RuntimeError(f"{obj.Label}: the guide failed its check: {report['summary']}")
        obj.Mesh = st_bridge.arrays_to_mesh(V, F)
        obj.PartsReport = json.dumps(placed) if placed else ""
        self.drop_thickness_map(obj)
        obj.Status = f"{report['summary']}; tubes {seconds:.3f} s"
        if "StabilityScore" in obj.PropertiesList:
            obj.StabilityScore = float(getattr(shell, "StabilityScore", 0.0))
        self.mark_drawings_out_of_date(obj)

    @staticmethod
    def mark_drawings_out_of_date(obj):
        """The guide's drawing pages (made by stdrawing, their SurgicalGuide naming it) show it as it was:
        marked OutOfDate, and their label says so, until a new drawing replaces them."""
        for page in obj.Document.Objects:
            if getattr(page, "SurgicalGuide", None) != obj.Name or "OutOfDate" not in page.PropertiesList:
                continue
            if not page.OutOfDate:
                page.OutOfDate = True
                page.Label = f"{page.Label} (out of date)"

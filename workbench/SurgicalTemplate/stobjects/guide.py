"""The surgical guide (Mesh::FeaturePython): the template shell with its tubes merged and their bores
cut by the kernel, and its saw slots (Slots: the case file's slot keys as JSON, since 0.3) cut in
their housings, checked as a printable solid; StabilityScore repeats its template's for expressions."""
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

    def onDocumentRestored(self, obj):
        self.properties_since_0_3(obj)

    @staticmethod
    def slots_text(slots):
        """The Slots property's text for slot dicts (numpy arrays as lists)."""
        def plain(v):
            return v.tolist() if isinstance(v, np.ndarray) else v
        return json.dumps([{k: plain(v) for k, v in s.items()} for s in slots]) if slots else ""

    @staticmethod
    def slots_of(obj):
        """The guide's slot dicts (case file keys); ValueError naming the guide for text that is not them."""
        text = getattr(obj, "Slots", "")
        if not text.strip():
            return []
        try:
            slots = json.loads(text)
        except ValueError as e:
            raise ValueError(f"{obj.Label}: Slots is not JSON: {e}") from None
        if not isinstance(slots, list):
            raise ValueError(f"{obj.Label}: Slots must be a JSON list of slots")
        return slots

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
        if tubes or slots:
            g = st_bridge.call(k.add_tubes, V, F, int(shell.InnerFaces), BV, BF, tubes,
                               chordal_tolerance=float(obj.Tolerance.Value),
                               clearance=float(shell.Clearance.Value), slots=slots)
            V, F = g["mesh"]
            seconds = g["seconds"]
        else:
            seconds = 0.0
        report = st_bridge.call(k.check_solid, V, F)
        if not report["valid"]:
            raise RuntimeError(f"{obj.Label}: the guide failed its check: {report['summary']}")
        obj.Mesh = st_bridge.arrays_to_mesh(V, F)
        self.drop_thickness_map(obj)
        obj.Status = f"{report['summary']}; tubes {seconds:.3f} s"
        if "StabilityScore" in obj.PropertiesList:
            obj.StabilityScore = float(getattr(shell, "StabilityScore", 0.0))

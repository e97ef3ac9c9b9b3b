"""The drawing's TechDraw page (Builder): front, top and side views of the guide (its line drawings),
one dimensioned detail per sleeve (the Tube objects themselves, exact solids, so that TechDraw's
dimensions find their edges) and per saw slot (stdrawing.slots), tables of the sleeves, the slots and
the template, the title block; and the checks and clean-up around it."""
import os

import numpy as np

import FreeCAD as App
import Part

import SurgicalTemplate_paths

from stdrawing.lines import guide_lines
from stdrawing.marks import ViewFrame, axis_labels, axis_marker
from stdrawing.marks import balloons as sleeve_balloons
from stdrawing.protocol import sleeve_rows, slot_rows, template_info, vec
from stdrawing.slots import dimension_slots, slot_details, slot_table
from stobjects.case_info import CaseInfo, author_name, case_info_of, viewer_side

SCALES = (20.0, 10.0, 5.0, 4.0, 3.0, 2.5, 2.0, 1.5, 1.0, 0.5, 0.4, 0.25, 0.2, 0.1)
TEXT = 3.5            # mm, text on the page
SMALL = 2.5           # mm, small text (table, notes)


# The workbench's templates (Resources/templates): a frame and an ISO 7200 title block 180 x 56 mm whose
# fields come from the case data (stobjects.case_info); page coordinates in mm, origin at the lower left.
_PAPERS = {
    "A3": {"template": "A3_Landscape_SurgicalGuide.svg", "size": (420.0, 297.0),
           "work": (10.0, 10.0, 410.0, 287.0), "title": (230.0, 10.0, 410.0, 66.0)},
    "A4": {"template": "A4_Landscape_SurgicalGuide.svg", "size": (297.0, 210.0),
           "work": (10.0, 10.0, 287.0, 200.0), "title": (107.0, 10.0, 287.0, 66.0)},
}

# Main views: name, caption, TechDraw Direction (from the object to the viewer), XDirection.
# First-angle arrangement (ISO, TechDraw's default): top view below the front view, the view from
# the left to the right of it.
_VIEWS = (
    ("Front", "FRONT  (view along +Y)", (0.0, -1.0, 0.0), (1.0, 0.0, 0.0)),
    ("Top", "TOP  (view along -Z)", (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),
    ("Left", "LEFT  (view along +X)", (-1.0, 0.0, 0.0), (0.0, -1.0, 0.0)),
)


_PX = 25.4 / 96.0   # mm per unit of a spreadsheet view (TechDraw draws its cells in 96 dpi pixels)


def paper_spec(paper):
    key = str(paper).upper()
    if key not in _PAPERS:
        raise ValueError(f"paper {paper!r}: use one of {', '.join(_PAPERS)}")
    spec = dict(_PAPERS[key], name=key)
    spec["path"] = os.path.join(SurgicalTemplate_paths.TEMPLATES, spec["template"])
    if not os.path.exists(spec["path"]):
        raise RuntimeError(f"drawing template {spec['path']} not found (reinstall the workbench)")
    return spec


def _scale_text(s):
    return f"{s:g}:1" if s >= 1 else f"1:{1.0 / s:g}"


def _fit_scale(width, height, room_w, room_h):
    for s in SCALES:
        if width * s <= room_w and height * s <= room_h:
            return s
    return SCALES[-1]


class Builder:
    """Adds the drawing's objects to the document and remembers them (to undo by hand when the
    document keeps no undo history)."""

    def __init__(self, doc, guide, paper, date):
        self.doc, self.guide, self.paper, self.date = doc, guide, paper, date
        self.created = []
        self.dimensions = {}

    def add(self, kind, name, label=None):
        obj = self.doc.addObject(kind, name)
        self.created.append(obj.Name)
        if label:
            obj.Label = label
        return obj

    def remove_created(self):
        for name in reversed(self.created):
            if self.doc.getObject(name) is not None:
                self.doc.removeObject(name)

    # The page: regions (x0, y0, x1, y1) in page mm: views at the top left, template data at the top
    # right, a band of sleeve details, the sleeve table beside the title block.
    def build(self):
        g, p = self.guide, self.paper
        (wx0, wy0, wx1, wy1), (tx0, _, _, ty1) = p["work"], p["title"]
        a3 = p["name"] == "A3"
        self.text = TEXT if a3 else 3.0
        self.small = SMALL if a3 else 2.0
        m = 5.0
        self.slots = slot_rows(g)
        for r in self.slots:
            if r["placed"] is None:
                raise ValueError(f"{g.Label}: slot '{r['name']}' has not been placed yet; recompute the guide")
        plan = self.detail_plan(wx1 - wx0 - 2 * m, 60.0 if a3 else 45.0)
        band = plan[1] * plan[4] if plan else 0.0
        self.page = self.add("TechDraw::DrawPage", "Drawing", f"{g.Label} drawing")
        template = self.add("TechDraw::DrawSVGTemplate", "DrawingTemplate", f"{g.Label} template")
        template.Template = p["path"]
        self.page.Template = template
        self.page.addProperty("App::PropertyString", "SurgicalGuide", "Surgical Template", "The guide drawn here")
        self.page.SurgicalGuide = g.Name
        self.page.addProperty("App::PropertyBool", "OutOfDate", "Surgical Template",
                              "The guide has been recomputed since this drawing was made: make it again")
        self.page.setEditorMode("OutOfDate", 1)
        self.group = self.add("App::DocumentObjectGroup", "DrawingData", f"{g.Label} drawing data")
        self.page.addProperty("App::PropertyString", "DrawingData", "Surgical Template", "Its lines and tables")
        self.page.DrawingData = self.group.Name
        info = self.info_table((wx1 - m, wy1 - m))
        if self.slots:
            slots = slot_table(self, self.slots, (wx1 - m, info[1] - m), self.small, _text_width)
            info = min(info, slots, key=lambda c: c[0])  # the views keep left of the wider table
        top = (wx0 + m, ty1 + band + 2 * m, info[0] - 2 * m, wy1 - m)
        self.main_views(top)
        self.details(plan, wx0 + m, ty1 + m + band)
        self.sleeve_table((wx0 + m, wy0 + m, tx0 - m, ty1))
        scale = _scale_text(self.scale)
        template.EditableTexts = self.title_block(template.EditableTexts, scale)
        return self.page

    def title_block(self, fields, scale):
        """The title block's fields: the case data (the guide's CaseInfo; without one, the guide's name as
        the case id and FreeCAD's author name as the designer), the title, number, scale, date, sheet."""
        g = self.guide
        info = case_info_of(g)
        values = CaseInfo.fields(info) if info is not None else {"CaseId": g.Label, "DesignedBy": author_name(),
                                                                   "DocumentType": "Surgical guide drawing"}
        values.update({"Title": g.Label, "Subtitle": "Surgical guide: sleeves and drilling plan",
                       "DrawingNumber": f"{values.get('CaseId') or g.Label}-G", "Scale": scale,
                       "IssueDate": self.date[:10], "Sheet": "1 / 1"})
        return {k: values.get(k, "") for k in fields}
        template.EditableTexts = {k: texts.get(k, v) for k, v in template.EditableTexts.items()}
        return self.page

    def feature(self, name, label, shape):
        f = self.add("Part::Feature", name, label)
        f.Shape = shape
        self.group.addObject(f)
        if App.GuiUp:
            f.ViewObject.Visibility = False
        return f

    def part_view(self, name, label, sources, direction, xdir, scale, x, y, caption):
        v = self.add("TechDraw::DrawViewPart", name, label)
        self.page.addView(v)
        v.Source = sources
        v.Direction, v.XDirection = App.Vector(*direction), App.Vector(*xdir)
        v.ScaleType = "Custom"
        v.Scale = scale
        v.X, v.Y = x, y
        v.Caption = caption
        return v

    def annotation(self, name, lines, x, y, size, style="Normal"):
        a = self.add("TechDraw::DrawViewAnnotation", name)
        self.page.addView(a)
        a.Text = lines
        a.TextSize = size
        a.TextStyle = style
        a.X, a.Y = x, y
        return a

    def main_views(self, region):
        x0, y0, x1, y1 = region
        box = self.guide.Mesh.BoundBox
        X, Y, Z = box.XLength, box.YLength, box.ZLength
        gap = 4.0 * self.text   # room for the sleeve names and the view titles
        self.scale = s = _fit_scale(X + Y, Z + Y, x1 - x0 - gap - 4.0 * self.text, y1 - y0 - 2.0 * gap)
        places = {"Front": (X * s / 2.0, -Z * s / 2.0), "Top": (X * s / 2.0, -Z * s - gap - Y * s / 2.0),
                  "Left": (X * s + gap + Y * s / 2.0, -Z * s / 2.0)}
        shapes = guide_lines(self.guide, [(d, x) for _, _, d, x in _VIEWS], self.arrays)
        self.views = {}
        placed = []   # (object, its box on the page)
        around = []   # balloons: placed relative to their view
        info = case_info_of(self.guide)
        patient = CaseInfo.frame(info) if info is not None else None
        for (name, title, d, x), lines in zip(_VIEWS, shapes):
            side = viewer_side(patient, d)
            if side:   # e.g. "ANTERIOR  (view along +Y)"
                title = side + title[title.index("  "):]
            shape, letters, foot, at_origin = axis_marker(lines, d, x, s)
            f = self.feature(f"DrawingLines{name}", f"{self.guide.Label} lines {name}", shape)
            cx, cy = places[name]
            v = self.part_view(f"View{name}", name, [f], d, x, s, cx, cy, "")
            self.views[name] = v
            half = _projected_half_size(shape, d, x) * s
            frame = ViewFrame(shape, d, x, s)
            mine = [(v, (cx - half[0], cy - half[1], cx + half[0], cy + half[1]))]
            mine += axis_labels(self, f"View{name}", frame, letters, foot, at_origin, cx, cy)
            balloons = sleeve_balloons(self, v, frame, cx, cy)
            low = min(box[1] for _, box in mine + balloons) - 1.2 * self.text
            t = self.annotation(f"View{name}Title", [title], cx, low, self.text)
            placed += mine + [(t, _text_box(title, self.text, cx, low))]
            around += balloons
        # Centre the arrangement with its balloons and titles in the region (balloons move with their view).
        boxes = [b for _, b in placed + around]
        bx0, by0 = min(b[0] for b in boxes), min(b[1] for b in boxes)
        bx1, by1 = max(b[2] for b in boxes), max(b[3] for b in boxes)
        dx, dy = (x0 + x1 - bx0 - bx1) / 2.0, (y0 + y1 - by0 - by1) / 2.0
        for obj, _ in placed:
            obj.X, obj.Y = _length(obj.X) + dx, _length(obj.Y) + dy

    def detail_plan(self, width, height):
        """(scale, lines, columns, cell width, cell height) of the sleeve and slot details in a band, or
        None; the scale is the sleeves' (each slot's detail fits its cell at its own)."""
        rows = sleeve_rows(self.guide)
        self.sizes = sleeve_sizes(self.guide)
        self.detail_scale = SCALES[0]
        count = len(self.sizes) + len(self.slots)
        if not count:
            return None
        L = max((r["length"] for r in rows), default=10.0)
        D = max((r["outer_diameter"] for r in rows), default=5.0)
        best = None
        for lines in (1, 2, 3):
            cols = -(-count // lines)
            cw, ch = width / cols, height / lines
            s = _fit_scale(L, D, cw - 8.0 * self.text, ch - 6.5 * self.text)
            if best is None or s > best[0]:
                best = (s, lines, cols, cw, min(ch, D * s + 6.5 * self.text))
        self.detail_scale = best[0]
        return best

    def details(self, plan, x0, y1):
        """One view per sleeve size (the first sleeve of that size, across its seam), titled with the
        numbers of the sleeves it stands for, then one per slot, in cells below y1."""
        self.details_of, self.slot_views = {}, {}
        if plan is None:
            return
        s, lines, cols, cw, ch = plan
        rows = sleeve_rows(self.guide)
        cells = []
        for i in range(len(self.sizes), len(self.sizes) + len(self.slots)):
            row, col = divmod(i, cols)
            cells.append((x0 + (col + 0.5) * cw, y1 - (row + 0.5) * ch + 0.8 * self.text, cw, ch))
        self.slot_views = slot_details(self, self.slots, cells, _fit_scale, _scale_text)
        for i, members in enumerate(self.sizes):
            r, tube = rows[members[0]], self.guide.Tubes[members[0]]
            row, col = divmod(i, cols)
            cx, cy = x0 + (col + 0.5) * cw, y1 - (row + 0.5) * ch + 0.8 * self.text
            a = r["direction"]
            d = np.cross(a, _seam_side(tube, a))
            d /= np.linalg.norm(d)
            v = self.part_view(f"Sleeve{i}", f"Sleeve {r['name']}", [tube], d, a, s, cx, cy, "")
            v.HardHidden = True
            R, rr = r["outer_diameter"] / 2.0 * s, r["inner_diameter"] / 2.0 * s
            low = cy - max(R, rr + 1.2 * self.text) - 1.4 * self.text
            title = _detail_title(members, rows, cw, self.text)
            self.annotation(f"Sleeve{i}Title", [f"{title}  ({_scale_text(s)})"], cx, low, self.text)
            # Which end is which, outside the diameters: the drill enters at the top (left).
            ends = r["length"] / 2.0 * s + 1.6 * self.text + 2.2 * self.small
            self.annotation(f"Sleeve{i}Top", ["top"], cx - ends, cy, self.small, "Italic")
            self.annotation(f"Sleeve{i}Bone", ["bone"], cx + ends, cy, self.small, "Italic")
            self.details_of[tube.Name] = v

    def dimension(self, view, ref, kind, fmt, x, y, label):
        dim = self.add("TechDraw::DrawViewDimension", "Dimension", label)
        dim.Type = kind
        dim.References2D = [(view, ref)]
        dim.FormatSpec = fmt
        dim.MeasureType = "Projected"
        self.page.addView(dim)
        dim.X, dim.Y = x, y
        return dim

    def dimension_details(self):
        """After a recompute: diameters and length of each sleeve, on its edges found by geometry; each
        slot's width."""
        self.slot_dimensions = dimension_slots(self)
        rows = sleeve_rows(self.guide)
        for members in self.sizes:
            r, tube = rows[members[0]], self.guide.Tubes[members[0]]
            v = self.details_of[tube.Name]
            s = v.Scale
            edges = _view_edges(v)
            n_visible = len(v.getVisibleEdges())

            def pick(want, visible, score):
                found = [(score(e), i) for i, e in edges if (i < n_visible) == visible and want(e)]
                if not found:
                    raise RuntimeError(f"{tube.Label}: no edge for a dimension in its detail view")
                return f"Edge{max(found)[1]}"

            def straight(e, axis, length):
                a, b = e.Vertexes[0].Point, e.Vertexes[-1].Point
                dx, dy = abs(a.x - b.x), abs(a.y - b.y)
                along, across = (dx, dy) if axis == "x" else (dy, dx)
                return across < 1e-6 and abs(along - length) < 1e-3

            def mid(e):
                a, b = e.Vertexes[0].Point, e.Vertexes[-1].Point
                return (a + b) * 0.5

            L, R, rr = r["length"], r["outer_diameter"] / 2.0, r["inner_diameter"] / 2.0
            length = pick(lambda e: straight(e, "x", L), True, lambda e: mid(e).y)
            outer = pick(lambda e: straight(e, "y", 2 * R), True, lambda e: mid(e).x)
            inner = pick(lambda e: straight(e, "y", 2 * rr), False, lambda e: -mid(e).x)
            gap = 1.6 * self.text
            # The axis, beyond both ends (a cosmetic line needs the computed view); the drill enters at
            # the left, the sleeve top.
            half = L / 2.0 + 0.6 * self.text / s
            v.makeCosmeticLine(App.Vector(-half, 0, 0), App.Vector(half, 0, 0), 4, 0.18, (0.0, 0.0, 0.0))
            self.dimensions[tube.Name] = [
                self.dimension(v, length, "DistanceX", "%.2f", 0.0, R * s + gap, f"{v.Label} length"),
                self.dimension(v, outer, "DistanceY", "⌀%.2f", L / 2.0 * s + gap, 0.0, f"{v.Label} outer diameter"),
                self.dimension(v, inner, "DistanceY", "⌀%.2f", -L / 2.0 * s - gap, 0.0,
                               f"{v.Label} inner diameter"),
            ]

    def sheet_table(self, sheet, first_col, rows, head_rows, widths, size, row_h):
        """Fills a block of `sheet` (the table's data, for the user) and returns its cell range."""
        cols = [_column(first_col + i) for i in range(len(widths))]
        for j, row in enumerate(rows):
            for i, text in enumerate(row):
                sheet.set(f"{cols[i]}{j + 1}", "'" + text if text else "")
        for i, w in enumerate(widths):
            sheet.setColumnWidth(cols[i], int(round(w / _PX)))
        for j in range(len(rows)):
            sheet.setRowHeight(str(j + 1), int(round(row_h / _PX)))
        last = f"{cols[-1]}{len(rows)}"
        if head_rows:
            sheet.setStyle(f"{cols[0]}1:{cols[-1]}{head_rows}", "bold")
            sheet.setAlignment(f"{cols[0]}1:{cols[-1]}{head_rows}", "center")
        if len(rows) > head_rows and len(cols) > 1:
            sheet.setAlignment(f"{cols[1]}{head_rows + 1}:{last}", "right")
        return f"{cols[0]}1", last

    def drawn_table(self, name, rows, widths, row_h, size, left, top, head_rows, span_first=False):
        """A table on the page: its grid as a symbol and each cell's text as an annotation (text the
        PDF keeps as text; a spreadsheet view's cells become outlines in it). Centred texts; header rows
        bold; span_first: the first row is one cell."""
        w, h = sum(widths), row_h * len(rows)
        px = 1.0 / _PX
        thin, thick = 0.18 * px, 0.35 * px
        xs = np.concatenate([[0.0], np.cumsum(widths)])
        lines = [f'<rect x="0" y="0" width="{w * px:.3f}" height="{h * px:.3f}" '
                 f'style="fill:none;stroke:#000000;stroke-width:{thick:.3f}"/>']
        for j in range(1, len(rows)):
            width = thick if j == head_rows else thin
            lines.append(f'<path d="M0,{j * row_h * px:.3f} H{w * px:.3f}" '
                         f'style="fill:none;stroke:#000000;stroke-width:{width:.3f}"/>')
        for i in range(1, len(widths)):
            y0 = row_h * px if span_first else 0.0
            lines.append(f'<path d="M{xs[i] * px:.3f},{y0:.3f} V{h * px:.3f}" '
                         f'style="fill:none;stroke:#000000;stroke-width:{thin:.3f}"/>')
        svg = (f'<svg xmlns="http://www.w3.org/2000/svg" version="1.1" width="{w * px:.3f}" '
               f'height="{h * px:.3f}" viewBox="0 0 {w * px:.3f} {h * px:.3f}">\n' + "\n".join(lines) + "\n</svg>\n")
        grid = self.add("TechDraw::DrawViewSymbol", name, name)
        self.page.addView(grid)
        grid.Symbol = svg
        grid.X, grid.Y = left + w / 2.0, top - h / 2.0
        for j, row in enumerate(rows):
            y = top - (j + 0.5) * row_h
            for i, text in enumerate(row):
                if not text:
                    continue
                x = left + (w / 2.0 if span_first and j == 0 else (xs[i] + xs[i + 1]) / 2.0)
                self.annotation(f"{name}Cell", [text], x, y, size, "Bold" if j < head_rows else "Normal")
        return w, h

    def info_table(self, corner):
        """Template data, its upper right corner at `corner`; returns the table's lower left corner."""
        info = template_info(self.guide, self.date)
        self.info_sheet = self.add("Spreadsheet::Sheet", "DrawingTemplateData", f"{self.guide.Label} template data")
        self.group.addObject(self.info_sheet)
        sx, sy, sz = info["size"]
        # Units in the first column: a sheet restored from a file reads "2.50 mm" as a number.
        rows = [["TEMPLATE", ""],
                ["Case", info["case"]],
                ["Thickness (mm)", f"{info['thickness']:.2f}"],
                ["Clearance (mm)", f"{info['clearance']:.2f}"],
                ["Volume (mm³)", f"{info['volume']:.1f}"],
                ["Size X × Y × Z (mm)", f"{sx:.1f} × {sy:.1f} × {sz:.1f}"],
                ["Sleeves", str(info["sleeves"])],
                ["Date", info["date"]]]
        size = self.small + 0.5
        widths = [_text_width(max((r[i] for r in rows), key=len), size) + 2.0 * size for i in range(2)]
        row_h = 2.0 * size
        self.sheet_table(self.info_sheet, 0, rows, 1, widths, size, row_h)
        self.info_sheet.mergeCells("A1:B1")
        w, h = sum(widths), row_h * len(rows)
        self.drawn_table("TemplateTable", rows, widths, row_h, size, corner[0] - w, corner[1], 1, span_first=True)
        return corner[0] - w, corner[1] - h

    def sleeve_table(self, region):
        x0, y0, x1, y1 = region
        self.sheet = self.add("Spreadsheet::Sheet", "DrawingSleeveTable", f"{self.guide.Label} sleeve table")
        self.group.addObject(self.sheet)
        head = ["No.", "Sleeve", "Entry X", "Entry Y", "Entry Z", "Azimuth", "Elevation", "Ø inner", "Ø outer",
                "Length", "Offset", "Top to entry", "Depth"]
        units = ["", "", "mm", "mm", "mm", "°", "°", "mm", "mm", "mm", "mm", "mm", "mm"]
        rows = [head, units]
        for number, r in enumerate(sleeve_rows(self.guide), start=1):
            rows.append([str(number), r["name"], *(f"{c:.2f}" for c in r["entry"]), f"{r['azimuth']:.1f}", f"{r['elevation']:.1f}",
                         f"{r['inner_diameter']:.2f}", f"{r['outer_diameter']:.2f}", f"{r['length']:.2f}",
                         f"{r['offset']:.2f}", f"{r['depth_to_entry']:.2f}",
                         f"{r['depth']:.2f}" if r["depth"] > 0 else "-"])
        notes = ["Direction of drilling, into the bone: azimuth in the XY plane from +X toward +Y, elevation "
                 "from the XY plane toward +Z.",
                 "Top to entry = offset + length: drill travel from the sleeve top to the bone. Depth: planned "
                 "depth into the bone. Drill: Ø inner."]
        size = self.small
        note_h = 2 * 1.6 * size + 2.0
        row_h = 2.0 * size
        widths = [_text_width(max((r[i] for r in rows), key=len), size) + 1.6 * size for i in range(len(head))]
        # Shrink to the room: the table and its notes.
        shrink = min(1.0, (x1 - x0) / sum(widths), (y1 - y0 - note_h) / (row_h * len(rows)),
                     (x1 - x0) / _text_width(max(notes, key=len), size))
        size, row_h, widths = size * shrink, row_h * shrink, [w * shrink for w in widths]
        self.sheet_table(self.sheet, 0, rows, 2, widths, size, row_h)
        w, h = self.drawn_table("SleeveTable", rows, widths, row_h, size, x0, y1, 2)
        self.notes = self.annotation("SleeveTableNotes", notes, x0 + (x1 - x0) / 2.0, y1 - h - note_h / 2.0,
                                     size * 0.9)
        self.notes.MaxWidth = x1 - x0


def sleeve_sizes(guide):
    """The guide's tubes grouped by size (bore, outer diameter, length, counterbore): lists of their
    indices, in the order of the tubes' first appearance."""
    groups = {}
    for i, t in enumerate(guide.Tubes):
        key = tuple(round(float(getattr(t, p).Value), 6) for p in ("InnerDiameter", "OuterDiameter", "Length")
                    if hasattr(t, p))
        key += tuple(round(float(getattr(t, p).Value), 6) for p in ("CounterboreDiameter", "CounterboreDepth")
                     if hasattr(t, p))
        groups.setdefault(key, []).append(i)
    return list(groups.values())


def _detail_title(members, rows, width, text):
    """"SLEEVE 16" or "SLEEVES 16, 13, 11" (the names of the sleeves of that size) or, where the names
    do not fit the cell, their numbers in the sleeve table: "SLEEVES 1-3, 5"."""
    head = "SLEEVE " if len(members) == 1 else "SLEEVES "
    title = head + ", ".join(rows[i]["name"] for i in members)
    if _text_width(title + "  (10:1)", text) <= width:
        return title
    runs, start = [], members[0]
    for a, b in zip(members, members[1:] + [None]):
        if b != a + 1:
            runs.append(f"{start + 1}" if a == start else f"{start + 1}-{a + 1}")
            start = b
    return head + "No. " + ", ".join(runs)


def _seam_side(tube, axis):
    """A unit vector across the axis towards the seam of the sleeve's cylinders. TechDraw 0.20 draws
    a seam as an edge, so the details look across it: the seam then lies on the outline."""
    entry = vec(tube.Entry)
    for e in tube.Shape.Edges:
        if isinstance(e.Curve, Part.Line):
            w = vec(e.Vertexes[0].Point) - entry
            w -= (w @ axis) * axis
            if np.linalg.norm(w) > 1e-6:
                return w / np.linalg.norm(w)
    w = np.cross(axis, [0.0, 0.0, 1.0])
    if np.linalg.norm(w) < 0.1:
        w = np.cross(axis, [1.0, 0.0, 0.0])
    return w / np.linalg.norm(w)


def _length(q):
    return float(getattr(q, "Value", q))


def _column(i):
    """Spreadsheet column name of index i (0 -> A)."""
    name = ""
    i += 1
    while i:
        i, k = divmod(i - 1, 26)
        name = chr(ord("A") + k) + name
    return name


def _text_box(text, size, x, y):
    """Page box of a one-line annotation centred at (x, y)."""
    w = _text_width(text, size) / 2.0
    return x - w, y - 0.7 * size, x + w, y + 0.7 * size


def _projected_half_size(shape, d, x):
    """Half width and height of a shape's box seen along d with x to the right."""
    d, x = np.asarray(d, dtype=float), np.asarray(x, dtype=float)
    frame = np.stack([x, np.cross(d, x)])
    b = shape.BoundBox
    corners = np.array([[px, py, pz] for px in (b.XMin, b.XMax) for py in (b.YMin, b.YMax)
                        for pz in (b.ZMin, b.ZMax)]) @ frame.T
    return (corners.max(axis=0) - corners.min(axis=0)) / 2.0


def _text_width(text, size):
    """Width estimate of a text in osifont (TechDraw's default), mm."""
    return 0.62 * size * len(text)


def _view_edges(view):
    """(index, edge) of all edges of a recomputed DrawViewPart, visible ones first (as 'EdgeN' counts)."""
    count = len(view.getVisibleEdges()) + len(view.getHiddenEdges())
    return [(i, view.getEdgeByIndex(i)) for i in range(count)]


def check_page(builder):
    """Every view computed, every dimension measuring what it documents."""
    for v in builder.page.Views:
        if "Invalid" in v.State:
            raise RuntimeError(f"{v.Label}: TechDraw failed on this view")
    rows = sleeve_rows(builder.guide)
    for members in builder.sizes:   # each size's detail, on its first sleeve
        r, tube = rows[members[0]], builder.guide.Tubes[members[0]]
        want = (r["length"], r["outer_diameter"], r["inner_diameter"])
        got = tuple(d.getRawValue() for d in builder.dimensions.get(tube.Name, ()))
        if len(got) != 3 or any(abs(a - b) > 1e-4 for a, b in zip(want, got)):
            raise RuntimeError(f"{tube.Label}: sleeve dimensions {got} do not match {want}")
    for r in builder.slots:
        dim = builder.slot_dimensions.get(r["name"])
        if dim is None or abs(dim.getRawValue() - r["width"]) > 1e-4:
            raise RuntimeError(f"slot '{r['name']}': its width dimension does not read {r['width']:.4f}")


def remove_drawings_of(guide, keep=None):
    """The guide's previous drawing (page, views, lines and tables), all but the page `keep`:
    make_drawing replaces it once the new one has passed its checks."""
    doc = guide.Document
    for page in [o for o in doc.Objects if o.TypeId == "TechDraw::DrawPage"]:
        if getattr(page, "SurgicalGuide", None) != guide.Name or page == keep:
            continue
        names = [v.Name for v in page.Views] + [page.Name]
        if page.Template is not None:
            names.append(page.Template.Name)
        group = doc.getObject(getattr(page, "DrawingData", "") or "")
        if group is not None:
            names += [o.Name for o in group.Group] + [group.Name]
        for name in names:
            if doc.getObject(name) is not None:
                doc.removeObject(name)

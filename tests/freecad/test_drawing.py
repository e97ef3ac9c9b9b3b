"""The documentation drawing of a guide, made headless: a TechDraw page with front, top and side views
and one dimensioned detail per sleeve, exported to PDF and SVG by FreeCAD's GUI in a subprocess under
Xvfb, and the drill protocol. The PDF, SVG and a PNG of the page are kept in the build's test-output
folder."""
import json
import os
import shutil
import subprocess

import numpy as np
import pytest

from fc_session import FREECAD_LIB, ROOT, install_workbench

CASE = os.path.join(ROOT, "examples", "cases", "maxilla-implants.json")


def drawing_of(tmp_path_factory, case, folder):
    """Runs drawing_session.py on a case; its result with the output folder."""
    if not os.path.exists(FREECAD_LIB):
        pytest.skip("FreeCAD is not installed")
    if not shutil.which("freecad") or not shutil.which("xvfb-run"):
        pytest.skip("FreeCAD GUI or Xvfb missing (the PDF/SVG export needs them)")
    home = tmp_path_factory.mktemp("fcdraw")
    install_workbench(str(home))
    out = os.path.join(os.environ.get("ST_TEST_OUTPUT_DIR", str(tmp_path_factory.mktemp("out"))), folder)
    shutil.rmtree(out, ignore_errors=True)
    os.makedirs(out)
    env = dict(os.environ, FREECAD_USER_HOME=str(home), FREECAD_USER_DATA=str(home), ST_OUT=out, ST_CASE=case)
    p = subprocess.run(["/usr/bin/python3", os.path.join(ROOT, "tests", "freecad", "drawing_session.py")],
                       capture_output=True, text=True, env=env, timeout=600)
    assert p.returncode == 0, p.stdout[-3000:] + p.stderr[-3000:]
    line = [l for l in p.stdout.splitlines() if l.startswith("RESULT ")]
    assert line, p.stdout[-3000:] + p.stderr[-3000:]
    result = json.loads(line[0][len("RESULT "):])
    result["out"] = out
    return result


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return drawing_of(tmp_path_factory, CASE, "drawing")


@pytest.fixture(scope="module")
def cutting(tmp_path_factory):
    """The drawing of the tibia cutting guide: two saw slots, two pins, a label."""
    return drawing_of(tmp_path_factory, os.path.join(ROOT, "examples", "cases", "tibia-osteotomy.json"),
                      "drawing-tibia")


def names(run):
    return [t["name"] for t in run["tubes"]]


def test_made_headless_in_reasonable_time(run):
    assert not run["gui_up"]          # so the export went through the GUI subprocess under Xvfb
    assert run["seconds"] < 90.0      # about 15 s on the project's machine


def test_pdf_and_svg_written_whole(run):
    pdf, svg = run["files"]["pdf"], run["files"]["svg"]
    assert pdf.endswith("guide-drawing.pdf") and svg.endswith("guide-drawing.svg")
    with open(pdf, "rb") as f:
        head = f.read(5)
    assert head == b"%PDF-" and os.path.getsize(pdf) > 20_000
    with open(svg, encoding="utf-8") as f:
        text = f.read()
    assert "<svg" in text and text.rstrip().endswith("</svg>") and len(text) > 50_000
    assert run["leftovers"] == []     # no temporary file stays behind


def test_pdf_text_names_the_case_the_sleeves_and_the_template(run):
    if not shutil.which("pdftotext"):
        pytest.skip("pdftotext missing (Debian package poppler-utils)")
    text = subprocess.run(["pdftotext", "-layout", run["files"]["pdf"], "-"], capture_output=True,
                          text=True).stdout
    assert run["case"] in text
    assert "Thickness" in text and "SLEEVE" in text
    # The example's five sleeves are of one size: one detail, titled with all their names.
    assert "SLEEVES " + ", ".join(names(run)) in text


def test_title_block_from_the_case_data_searchable_in_a_clean_pdf(run):
    """Every field the user set is in the title block and in the PDF as text; poppler reads the PDF
    without an error."""
    block = run["page"]["title_block"]
    for key, value in run["case_data"].items():
        assert block[key] == value
    assert block["Title"] == run["case"] and block["Sheet"] == "1 / 1" and block["Scale"].endswith(":1")
    assert "Colour" in run["case_data_error"] and "CaseId" in run["case_data_error"]
    if not shutil.which("pdftotext"):
        pytest.skip("pdftotext missing (Debian package poppler-utils)")
    p = subprocess.run(["pdftotext", run["files"]["pdf"], "-"], capture_output=True, text=True)
    assert p.returncode == 0 and p.stderr == ""
    words = " ".join(p.stdout.split())
    for value in run["case_data"].values():
        assert value in words, value
    assert "REV." in words and "DOCUMENT STATUS" in words and "MX-2026-0412-G" in words


def test_page_looks_like_a_drawing(run):
    """The PDF rendered: ink on paper, kept as a PNG to look at."""
    if not shutil.which("pdftoppm"):
        pytest.skip("pdftoppm missing (Debian package poppler-utils)")
    base = os.path.join(run["out"], "guide-drawing")
    subprocess.run(["pdftoppm", "-png", "-r", "100", "-singlefile", run["files"]["pdf"], base], check=True,
                   capture_output=True)
    gray = subprocess.run(["pdftoppm", "-gray", "-r", "40", "-singlefile", run["files"]["pdf"]],
                          check=True, capture_output=True).stdout
    # Binary PGM: "P5\n<w> <h>\n255\n" then the pixels.
    header = gray.split(b"\n", 3)
    w, h = map(int, header[1].split())
    pixels = np.frombuffer(header[3][:w * h], dtype=np.uint8).reshape(h, w)
    assert w > h > 300                                # A3 landscape
    ink = (pixels < 128).mean()
    assert 0.005 < ink < 0.2


def test_front_top_and_side_views_of_the_guide(run):
    views = {v["label"]: v for v in run["views"]}
    for name, direction in (("Front", [0, -1, 0]), ("Top", [0, 0, 1]), ("Left", [-1, 0, 0])):
        v = views[name]
        assert v["source_types"] == ["Part::Feature"]          # the guide's lines, computed from its mesh
        assert v["direction"] == pytest.approx(direction)
        assert v["visible_edges"] > 30 and "Invalid" not in v["state"]
    assert len({views[n]["scale"] for n in ("Front", "Top", "Left")}) == 1
    # First-angle arrangement: top view below the front view, the view from the left right of it.
    assert views["Top"]["y"] < views["Front"]["y"] and views["Top"]["x"] == pytest.approx(views["Front"]["x"])
    assert views["Left"]["x"] > views["Front"]["x"] and views["Left"]["y"] == pytest.approx(views["Front"]["y"])


def sizes(run):
    """{(inner, outer, length): [tube names]} of a drawing's guide."""
    out = {}
    for t in run["tubes"]:
        out.setdefault((t["inner_diameter"], t["outer_diameter"], t["length"]), []).append(t["name"])
    return out


def check_one_dimensioned_detail_per_size(run):
    details = {v["sources"][0]: v for v in run["views"] if v["label"].startswith("Sleeve ")}
    by_size = sizes(run)
    assert sorted(details) == sorted(names[0] for names in by_size.values())
    for (inner, outer, length), members in by_size.items():
        view = details[members[0]]
        assert view["hidden_edges"] > 0                        # the bore, dashed
        dims = [d for d in run["dimensions"] if d["view"] == view["name"]]
        assert len(dims) == 3
        assert all("Invalid" not in d["state"] for d in dims)
        assert sorted(d["value"] for d in dims) == pytest.approx(sorted([length, outer, inner]), abs=1e-6)
        assert sum(d["text"].startswith("⌀") for d in dims) == 2   # two diameters
        title = [v for v in run["views"] if v["name"] == view["name"] + "Title"][0]["text"][0]
        assert title.startswith("SLEEVE " if len(members) == 1 else "SLEEVES ")
        assert all(name in title for name in members)
    return len(details)


def test_one_dimensioned_detail_per_sleeve_size(run, cutting):
    assert check_one_dimensioned_detail_per_size(run) == 1           # five sleeves of one size
    assert check_one_dimensioned_detail_per_size(cutting) == 2       # a K-wire and a screw


def test_tables_of_sleeves_and_template(run):
    grids = {v["label"] for v in run["views"] if v.get("type") == "TechDraw::DrawViewSymbol"}
    assert grids == {"SleeveTable", "TemplateTable"}
    cells = [" ".join(v["text"]) for v in run["views"] if v.get("type") == "TechDraw::DrawViewAnnotation"]
    for text in ["Sleeve", "Entry X", "Azimuth", "Elevation", "Ø inner", "Ø outer", "Length", "Offset",
                 "Thickness (mm)", "Clearance (mm)", "Volume (mm³)", "Size X × Y × Z (mm)", run["case"],
                 *names(run)]:
        assert text in cells
    assert any("azimuth" in c and "elevation" in c for c in cells)   # the angles are explained
    # The numbers also in spreadsheets, for the user.
    sheets = run["sheets"]
    assert any(c[:3] == ["No.", "", "1"] and c[3] == names(run)[0] for c in sheets.values())


def test_numbered_balloons_keyed_to_the_sleeve_table_never_overlap(run):
    """Each main view has a balloon per sleeve numbered as its row in the sleeve table, the leader from
    the sleeve's top; no two bubbles of a view overlap (3.5 mm text: bubbles about 3.3 mm in radius)."""
    numbers = [str(i) for i in range(1, len(names(run)) + 1)]
    for view in ("Front", "Top", "Left"):
        mine = [b for b in run["balloons"] if b["view"] == view]
        assert sorted(b["text"] for b in mine) == sorted(numbers)
        assert all("Invalid" not in b["state"] for b in mine)
        scale = {v["label"]: v["scale"] for v in run["views"] if "scale" in v}[view]
        at = np.array([b["at"] for b in mine]) * scale       # page mm (balloons keep unscaled positions)
        gaps = np.linalg.norm(at[:, None] - at[None], axis=2) + np.eye(len(at)) * 1e9
        assert gaps.min() >= 2.2 * 0.95 * 3.5 - 1e-9
        leaders = np.linalg.norm(at - np.array([b["origin"] for b in mine]) * scale, axis=1)
        assert leaders.min() > 3.0 and leaders.max() < 60.0


def test_views_named_anatomically_when_the_patient_frame_is_given(run, cutting):
    """The maxilla's case data say its scan is in LPS: the views are named by the side they are seen
    from; the tibia's do not: front, top, left."""
    def titles(r):
        return {v["name"]: v["text"][0] for v in r["views"] if v["name"] in ("ViewFrontTitle", "ViewTopTitle",
                                                                              "ViewLeftTitle")}
    assert titles(run) == {"ViewFrontTitle": "ANTERIOR  (view along +Y)", "ViewTopTitle": "SUPERIOR  (view along -Z)",
                           "ViewLeftTitle": "RIGHT  (view along +X)"}
    assert titles(cutting) == {"ViewFrontTitle": "FRONT  (view along +Y)", "ViewTopTitle": "TOP  (view along -Z)",
                               "ViewLeftTitle": "LEFT  (view along +X)"}
    assert "XYZ" in run["frame_error"] and "LPS" in run["frame_error"]


def test_each_main_view_has_an_axis_marker_with_scan_coordinates(run, cutting):
    """Each main view shows the scan axes that lie in it, pointing the way they go in that view, from a
    foot labelled with its scan coordinates: the box corner the view puts at its lower left, rounded
    outward to whole mm (or the scan origin, when the view shows it)."""
    # view: (axis to the right and its sign, axis up), as the views look (first-angle, scan frame).
    seen = {"Front": (("X", 1), "Z"), "Top": (("X", 1), "Y"), "Left": (("Y", -1), "Z")}
    for r in (run, cutting):
        notes = {v["name"]: v for v in r["views"] if v.get("type") == "TechDraw::DrawViewAnnotation"}
        lo, hi = np.array(r["guide_box"][:3]), np.array(r["guide_box"][3:])
        for view, ((right, sign), up) in seen.items():
            foot = notes[f"View{view}AxisFoot"]
            words = foot["text"][0]
            assert words.startswith("(") and words.endswith(")"), words
            xyz = np.array([float(c) for c in words[1:-1].split(",")])
            assert np.all(xyz == np.round(xyz))
            for k, name in enumerate("XYZ"):
                if name == right and sign < 0:
                    assert hi[k] <= xyz[k] < hi[k] + 1.0
                elif name in (right, up):
                    assert lo[k] - 1.0 < xyz[k] <= lo[k]
            letter_r, letter_u = notes[f"View{view}Axis{right}"], notes[f"View{view}Axis{up}"]
            assert sign * (letter_r["x"] - foot["x"]) > 8.0 and abs(letter_r["y"] - foot["y"]) < 5.0
            assert letter_u["y"] - foot["y"] > 8.0 and abs(letter_u["x"] - foot["x"]) < 1e-6
            assert not any(f"View{view}Axis{n}" in notes for n in "XYZ" if n not in (right, up))


def test_protocol_gives_the_depth_of_every_sleeve(run):
    with open(run["files"]["protocol_path"], encoding="utf-8") as f:
        assert f.read() == run["protocol"]
    rows = [[c.strip() for c in line.strip().strip("|").split("|")] for line in run["protocol"].splitlines()
            if line.startswith("|") and not line.startswith("|-")]
    head, body = rows[0], {r[0]: dict(zip(rows[0], r)) for r in rows[1:]}
    assert "Depth to entry" in head and "Drill diameter" in head
    assert sorted(body) == sorted(names(run))
    for tube in run["tubes"]:
        row = body[tube["name"]]
        assert float(row["Depth to entry"]) == pytest.approx(tube["offset"] + tube["length"], abs=1e-6)
        assert float(row["Drill diameter"]) == pytest.approx(tube["inner_diameter"], abs=1e-6)
        if tube["depth"] > 0:  # the example plans 10 mm implants
            assert float(row["Planned depth"]) == pytest.approx(tube["depth"], abs=1e-6)
            assert float(row["Total depth"]) == pytest.approx(tube["offset"] + tube["length"] + tube["depth"], abs=1e-6)
        else:
            assert row["Total depth"] == "-"


def test_one_undo_step_and_a_new_drawing_replaces_the_old(run):
    undo = run["objects_after_undo"]
    assert undo["pages"] == 0 and undo["after"] < undo["before"]
    assert run["pages_after_second_drawing"] == 1


def test_a_recomputed_guide_marks_its_drawing_out_of_date(run):
    state = run["drawing_after_change"]
    assert not state["fresh"]["out_of_date"] and "out of date" not in state["fresh"]["label"]
    assert state["out_of_date"] and state["label"] == state["fresh"]["label"] + " (out of date)"
    assert not state["new"]["out_of_date"] and "out of date" not in state["new"]["label"]


def test_clear_errors(run):
    e = run["errors"]
    assert e["paper"].startswith("ValueError") and "B7" in e["paper"]
    assert e["not_a_guide"].startswith("ValueError") and "not a surgical guide" in e["not_a_guide"]
    assert e["empty"].startswith("ValueError") and "EmptyGuide" in e["empty"] and "empty" in e["empty"]


def test_a_cutting_guide_drawing_has_a_detail_and_a_table_row_per_slot(cutting):
    """Each saw slot in a detail (its housing seen down the saw's travel) whose dimension reads its width,
    blade + 2 x clearance, and in a table with its plane, travel, blade and width; the PDF keeps them as
    text."""
    widths = {d["view"]: d["value"] for d in cutting["dimensions"] if d["view"].startswith("Slot")}
    assert len(widths) == 2
    assert all(w == pytest.approx(0.89 + 2 * 0.1, abs=1e-6) for w in widths.values())
    slot_views = [v for v in cutting["views"] if v["name"].startswith("Slot") and "visible_edges" in v]
    assert len(slot_views) == 2 and all(v["visible_edges"] >= 8 for v in slot_views)
    table = cutting["sheets"]["tibia-osteotomy slot table"]
    assert table[:2] == ["Slot", "proximal cut"]
    if shutil.which("pdftotext"):
        text = subprocess.run(["pdftotext", "-layout", cutting["files"]["pdf"], "-"], capture_output=True,
                              text=True).stdout
        for words in ("SLOT proximal cut", "SLOT distal cut", "1.09", "0.89"):
            assert words in text, words

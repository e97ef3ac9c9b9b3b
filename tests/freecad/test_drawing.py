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
    assert head == b"%PDF-" and os.path.getsize(pdf) > 50_000
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
    for name in names(run):
        assert f"SLEEVE {name}" in text


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


def test_one_dimensioned_detail_per_sleeve(run):
    details = {v["sources"][0]: v for v in run["views"] if v["label"].startswith("Sleeve ")}
    assert sorted(details) == sorted(names(run))
    for tube in run["tubes"]:
        view = details[tube["name"]]
        assert view["hidden_edges"] > 0                        # the bore, dashed
        dims = [d for d in run["dimensions"] if d["view"] == view["name"]]
        assert len(dims) == 3
        assert all("Invalid" not in d["state"] for d in dims)
        values = sorted(d["value"] for d in dims)
        want = sorted([tube["length"], tube["outer_diameter"], tube["inner_diameter"]])
        assert values == pytest.approx(want, abs=1e-6)
        assert sum(d["text"].startswith("⌀") for d in dims) == 2   # two diameters


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
    assert any(c[0] == "Sleeve" and c[2] == names(run)[0] for c in sheets.values())


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

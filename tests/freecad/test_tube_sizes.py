"""Tube sizes as diameters (as the catalogue, drawings and vendors give them): an expression drives the
guide, and documents of versions before 0.4 (radii, plain vectors) open with their tubes migrated, the
guide the same."""
import os

import pytest

from fc_session import ROOT, run_headless


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(tmp_path_factory, "tube_sizes_headless.py",
                        ST_CASE=os.path.join(ROOT, "examples", "cases", "tibia-osteotomy.json"))


def test_tubes_have_diameters_positions_and_directions(run):
    loaded = run["loaded"]
    assert loaded["valid"]
    for name, tube in loaded["tubes"].items():
        spec = run["spec"][name]
        assert tube["inner"] == pytest.approx(2 * spec["inner_radius"]) and tube["inner"] > 0
        assert tube["outer"] == pytest.approx(2 * spec["outer_radius"])
        assert tube["types"] == ["App::PropertyPosition", "App::PropertyDirection"]
        assert tube["radius_properties"] == []
    screw = loaded["tubes"]["distal screw"]
    assert screw["counterbore"] == pytest.approx(2 * run["spec"]["distal screw"]["counterbore"]["radius"])


def test_a_spreadsheet_expression_drives_the_outer_diameter_and_the_guide(run):
    driven, wider = run["driven"], run["driven_wider"]
    assert driven["tubes"]["distal screw"]["outer"] == pytest.approx(6.4)
    assert driven["tubes"]["distal screw"]["expressions"] == {"OuterDiameter": "Spreadsheet.D"}
    assert wider["tubes"]["distal screw"]["outer"] == pytest.approx(7.0)
    assert driven["valid"] and wider["valid"]
    assert driven["volume"] > run["loaded"]["volume"] + 1.0      # 6.0 -> 6.4 mm: a thicker sleeve
    assert wider["volume"] > driven["volume"] + 1.0


def test_a_document_from_before_0_4_opens_migrated_with_the_same_guide(run):
    assert run["old_layout"]["distal screw"] == ["CounterboreRadius", "InnerRadius", "OuterRadius"]
    reopened, recomputed = run["reopened"], run["recomputed"]
    for name, tube in reopened["tubes"].items():
        want = run["driven_wider"]["tubes"][name]
        assert tube["radius_properties"] == []
        assert tube["types"] == ["App::PropertyPosition", "App::PropertyDirection"]
        for key in ("inner", "outer", "counterbore"):
            assert tube[key] == pytest.approx(want[key], abs=1e-9)
        assert tube["entry"] == pytest.approx(want["entry"]) and tube["direction"] == pytest.approx(want["direction"])
    # The radius expression, doubled: the diameter still follows the spreadsheet.
    expression = reopened["tubes"]["distal screw"]["expressions"]["OuterDiameter"]
    assert expression.startswith("2 *") and "Spreadsheet.D" in expression
    assert recomputed["valid"] and recomputed["volume"] == pytest.approx(run["driven_wider"]["volume"], rel=1e-9)
    assert run["reopened_driven"]["tubes"]["distal screw"]["outer"] == pytest.approx(6.4)
    assert run["reopened_driven"]["volume"] == pytest.approx(run["driven"]["volume"], rel=1e-9)

"""Plans, validation and the tube panel in a real FreeCAD window under Xvfb: a 3D Slicer plan imported by
the Import plan command onto a bare bone (the sleeve preset asked for), the Validate panel's
inspection and thickness map (its screenshot shows the green seat), tubes from a preset with the
direction from a second clicked point and from the view; the script FreeCAD recorded replays to the
same tree."""
import math

import pytest

from fc_session import run_gui


@pytest.fixture(scope="module")
def session(tmp_path_factory):
    return run_gui(tmp_path_factory, "gui_plan_session.py", "gui-plan-result.json")


def test_import_plan_command_builds_the_guide_asking_for_the_preset(session):
    assert "SurgicalTemplate_ImportPlan" in session["commands"]
    r = session["import"]
    assert r["ok"] and r["asked"] == [["left", "right"]]
    assert r["guides"] == 1 and r["tubes"] == ["left", "right"] and r["presets"] == ["drill-2.5", "drill-2.5"]
    assert "Invalid" not in r["state"]


def test_validate_panel_inspects_and_colours_the_guide(session):
    v = session["validate"]
    assert v["error"] is None and v["passed"], v["summary"]
    assert [b["open"] for b in v["bores"]] == [True, True] and v["in_bone"] == 0
    assert v["colours"] == v["facets"] and v["coloring"]
    assert "Touched" not in v["state"]  # showing the map does not make the guide recompute
    # The removal check along the template's insertion direction is shown, the arrow is drawn, and the
    # undercut map covers the bone under the template.
    assert v["removal_text"] and ("comes off" in v["removal_text"] or "meets the bone" in v["removal_text"])
    assert v["arrow"] == 1
    assert v["map_faces"] == v["region_faces"] > 0
    # Stability: the panel's rows, the overlay's contacts (one green point each), a marker per free
    # motion and the press point; the guide's StabilityScore repeats its template's, 0..1.
    s = v["stability"]
    assert s["text"].startswith("score ") and s["press_text"].startswith("near (")
    assert s["contacts"] > 100 and s["shown"] == {"contacts": s["contacts"], "motions": s["motions"], "press": 1}
    assert s["hidden"] == {"contacts": 0, "motions": 0, "press": 0}
    assert s["green"]["on"] > s["green"]["off"] + 0.005  # the contacts drawn over the guide
    assert 0.0 <= s["score"] <= 1.0 and 0.0 <= s["template_score"] <= 1.0
    assert s["guide_score"] == s["template_score"] and "stability" in s["template_status"]
    green, red = session["map_shot"]["green_red"]
    assert green > 0.005 and red < 0.001  # the seat seen from the bone's side; nothing in the bone
    assert session["coloring_off"] is False
    assert session["map_after_recompute"] == 0


def test_validate_shows_a_colour_bar_and_reads_the_map_where_clicked(session):
    """The bar runs from the bone to beyond the outer surface with the distances marked; a click on the
    guide reads the distance of the facet under the cursor, as the map colours it."""
    v = session["validate"]
    bar = v["bar"]
    assert bar["shown"] and bar["height"] >= 150
    distances = [d for d, _ in bar["stops"]]
    assert distances == sorted(distances) and distances[0] < 0 < distances[1] + 1e-9
    assert "seated" in bar["stops"][1][1] and "outer surface" in bar["stops"][3][1]
    readings = v["readings"]
    assert len(readings) == 3
    for r in readings:
        assert r["distance"] == r["map"]
        # The facet under the cursor is the one aimed at or a neighbour sharing the spot.
        gap = sum((a - b) ** 2 for a, b in zip(r["point"], r["aimed_at"])) ** 0.5
        assert gap < 1.0
        assert f"{abs(r['distance']):.2f} mm" in r["text"]


def test_tube_from_a_preset_and_a_second_point(session):
    r = session["second_point"]
    a, b = r["clicks"]
    assert a and b and r["tubes"] == 1
    along = [q - p for p, q in zip(a, b)]
    length = math.sqrt(sum(x * x for x in along))
    assert r["direction"] == pytest.approx([x / length for x in along], abs=1e-4)
    assert r["depth"] == pytest.approx(length, abs=1e-3)
    k = r["kwire"]
    assert r["sizes"] == pytest.approx([k["inner_radius"], k["outer_radius"], k["length"], k["offset"]])
    assert r["preset"] == "kwire-2.0"


def test_tube_against_the_clicked_facets_normal(session):
    assert session["normal_click"]
    n = session["normal"]
    assert n["tube"] == pytest.approx([-x for x in n["facet_normal"]], abs=1e-4)


def test_tube_along_the_view(session):
    assert session["view_click"]
    assert session["view_direction"]["tube"] == pytest.approx(session["view_direction"]["view"], abs=1e-4)
    assert "Invalid" not in session["final_state"]  # the guide recomputes whole without the ad-hoc tubes


def test_recorded_macro_replays_to_the_same_tree(session):
    macro = "\n".join(session["macro"])
    assert "SurgicalTemplate.make_bone(" in macro and "SurgicalTemplate.load_plan(" in macro
    assert macro.count("SurgicalTemplate.make_tube(") == 3
    a, b = session["recorded"], session["replayed"]
    assert b["objects"] == a["objects"]
    assert b["points"] == a["points"]
    assert len(b["tubes"]) == len(a["tubes"]) == 5
    for ta, tb in zip(a["tubes"], b["tubes"]):
        assert tb[0] == ta[0] and tb[5] == ta[5]
        assert tb[1] + tb[2] + tb[3:5] == pytest.approx(ta[1] + ta[2] + ta[3:5], abs=1e-3)  # recorded to 4-5 decimals
    assert b["state"] == a["state"] and b["facets"] == a["facets"]
    assert b["volume"] == pytest.approx(a["volume"], rel=1e-9)


def test_the_gui_keeps_running_while_the_kernel_works(session):
    r = session["responsive"]
    assert "Invalid" not in r["state"] and r["seconds"] > 0.2
    assert r["ticks"] >= 0.3 * r["seconds"] / 0.02, r  # a 20 ms timer fired through the recompute

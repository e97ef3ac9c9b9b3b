"""The skirt in the workbench: a template whose border lies where the bone turns under (a sphere cut 20
degrees beyond its equator, put on from above) keeps covering down to the border, reports the skirt's
area and still comes off."""
import math

import pytest

from fc_session import run_headless


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    return run_headless(tmp_path_factory, "skirt_headless.py")


def test_the_template_hangs_a_skirt_down_to_the_border_and_comes_off(run):
    assert "Invalid" not in run["state"] and run["valid"], run["status"]
    depth = -20 * math.cos(math.radians(110))  # the border's depth below the equator
    band = 2 * math.pi * 20 * depth            # the cylinder from the equator down to it
    assert run["skirt_area"] == pytest.approx(band, rel=0.05)
    assert run["lowest"] == pytest.approx(-depth, abs=0.1)
    assert run["removable"]
    assert "skirt" in run["status"]

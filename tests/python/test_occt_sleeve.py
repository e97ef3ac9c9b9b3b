"""The OpenCASCADE sleeves from Python: BREP text of one solid, a closed mesh on the exact surface."""
import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def occt(stk):
    if not stk.has_occt:
        pytest.skip("stkernel was built without OpenCASCADE (ST_WITH_OCCT, see the CMake warning)")
    return stk


ENTRY = np.array([12.5, -40.0, 7.25])
DIRECTIONS = [(0, 0, 1), (0, -1, 0), (1, 2, -3), (-0.3, 0.5, 0.81)]


def cylindrical(points, entry, direction):
    axis = -np.asarray(direction, float) / np.linalg.norm(direction)
    d = points - entry
    z = d @ axis
    rho = np.linalg.norm(d - z[:, None] * axis, axis=1)
    return z, rho


def test_has_occt_is_a_bool(stk):
    assert stk.has_occt in (True, False)


@pytest.mark.parametrize("direction", DIRECTIONS)
def test_tessellate_sleeve_is_a_closed_solid_on_the_surface(occt, direction):
    r, R, L, offset, d = 2.0, 3.0, 20.0, 1.5, 0.01
    v, f = occt.tessellate_sleeve(ENTRY, direction, r, R, L, offset, linear_deflection=d)
    assert v.dtype == np.float64 and v.ndim == 2 and v.shape[1] == 3
    assert np.issubdtype(f.dtype, np.integer) and f.ndim == 2 and f.shape[1] == 3
    assert f.min() >= 0 and f.max() < len(v)
    report = occt.check_solid(v, f)
    assert report["valid"], report["summary"]
    assert report["components"] == 1

    z, rho = cylindrical(v, ENTRY, direction)
    tol = 1e-9
    assert rho.min() >= r - tol and rho.max() <= R + tol
    assert z.min() >= offset - tol and z.max() <= offset + L + tol
    # Vertices lie on the walls or on the caps.
    on_wall = (np.abs(rho - r) < tol) | (np.abs(rho - R) < tol)
    on_cap = (np.abs(z - offset) < tol) | (np.abs(z - offset - L) < tol)
    assert (on_wall | on_cap).all()

    # Within the chordal error of the deflection: the outer wall loses at most pi (R^2 - (R-d)^2) L,
    # the inner wall (hole shrinking) adds at most pi (r^2 - (r-d)^2) L.
    exact = math.pi * (R * R - r * r) * L
    assert exact - math.pi * L * (R * R - (R - d) ** 2) <= report["volume"]
    assert report["volume"] <= exact + math.pi * L * (r * r - (r - d) ** 2)


def test_finer_deflection_gives_a_closer_volume(occt):
    r, R, L = 1.6, 2.5, 30.0
    exact = math.pi * (R * R - r * r) * L
    errors = []
    for d in (0.1, 0.01, 0.001):
        v, f = occt.tessellate_sleeve(ENTRY, (1, 2, -3), r, R, L, 0.0, linear_deflection=d, angular_deflection=1.0)
        errors.append(abs(occt.check_solid(v, f, self_intersections=False)["volume"] - exact))
    assert errors[1] < 0.3 * errors[0] and errors[2] < 0.3 * errors[1]


def test_sleeve_brep_is_text_of_one_solid(occt):
    text = occt.sleeve_brep(ENTRY, (1, 2, -3), 2.0, 3.0, 20.0, 1.5, name="pedicle-left")
    assert isinstance(text, str)
    assert "CASCADE Topology V2" in text[:64]
    # One solid, one shell, four faces (outer and inner wall, two caps); no mesh in the text.
    lines = text.splitlines()
    shapes = [l.strip() for l in lines if l.strip() in ("So", "Sh", "Fa", "Co", "CS")]
    assert shapes.count("So") == 1 and shapes.count("Sh") == 1 and shapes.count("Fa") == 4
    assert "Co" not in shapes and "CS" not in shapes
    assert "Triangulations 0" in text or "Triangulations" not in text


def test_bad_input_raises_value_error(occt):
    with pytest.raises(ValueError, match="direction"):
        occt.sleeve_brep(ENTRY, (0, 0, 0), 2.0, 3.0, 20.0, 1.5)
    with pytest.raises(ValueError, match="pedicle-left.*entry"):
        occt.sleeve_brep((float("nan"), 0, 0), (0, 0, 1), 2.0, 3.0, 20.0, 1.5, name="pedicle-left")
    with pytest.raises(ValueError, match="outer_radius"):
        occt.sleeve_brep(ENTRY, (0, 0, 1), 3.0, 3.0, 20.0, 1.5)
    with pytest.raises(ValueError, match="outer_radius"):
        occt.tessellate_sleeve(ENTRY, (0, 0, 1), 3.5, 3.0, 20.0, 1.5)
    with pytest.raises(ValueError, match="linear_deflection"):
        occt.tessellate_sleeve(ENTRY, (0, 0, 1), 2.0, 3.0, 20.0, 1.5, linear_deflection=-0.01)
    with pytest.raises(ValueError, match="linear_deflection"):
        occt.tessellate_sleeve(ENTRY, (0, 0, 1), 2.0, 3.0, 20.0, 1.5, linear_deflection=float("nan"))
    with pytest.raises(ValueError, match="angular_deflection"):
        occt.tessellate_sleeve(ENTRY, (0, 0, 1), 2.0, 3.0, 20.0, 1.5, angular_deflection=0.0)
    with pytest.raises(ValueError, match="three coordinates"):
        occt.tessellate_sleeve(ENTRY[:2], (0, 0, 1), 2.0, 3.0, 20.0, 1.5)

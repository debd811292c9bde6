"""satflock.characterize against hand-computed five elements of simple shapes."""

import math

import numpy as np
import pytest

import satflock


def regular_tetrahedron(edge_m):
    """Vertices of a regular tetrahedron of edge `edge_m` centred on the origin (every pair at edge_m)."""
    s = edge_m / (2.0 * math.sqrt(2.0))
    return s * np.array([[1, 1, 1], [1, -1, -1], [-1, 1, -1], [-1, -1, 1]], dtype=float)


def test_regular_tetrahedron():
    a = 10.0
    e = satflock.characterize(regular_tetrahedron(a))
    assert e["n"] == 4
    np.testing.assert_allclose(e["r_o_m"], 0.0, atol=1e-14)
    # Circumradius of a regular tetrahedron: a sqrt(6) / 4.
    assert e["d_max_m"] == pytest.approx(a * math.sqrt(6.0) / 4.0, rel=1e-14)
    assert e["diameter_m"] == pytest.approx(a, rel=1e-14)
    assert e["d_min_m"] == pytest.approx(a, rel=1e-14)
    # m_i = a/2 for all; M = (a + a/2 + a/2) / 2 = a; L = 4 (a/2)^3 / a^3 = 1/2.
    assert e["uniformity_l"] == pytest.approx(0.5, rel=1e-14)
    assert "v_o_mps" not in e


def test_square_with_radii_and_velocities():
    a = 3.0
    square = np.array([[0, 0, 0], [a, 0, 0], [a, a, 0], [0, a, 0]], dtype=float)
    velocities = np.array([[1, 0, 0], [0, 2, 0], [0, 0, 3], [-1, -2, -3]], dtype=float)
    e = satflock.characterize(square, radii=0.25, velocities=velocities)
    np.testing.assert_allclose(e["r_o_m"], [a / 2, a / 2, 0.0], rtol=1e-15)
    np.testing.assert_allclose(e["v_o_mps"], [0.0, 0.0, 0.0], atol=1e-15)
    assert e["d_max_m"] == pytest.approx(a / math.sqrt(2.0), rel=1e-14)
    assert e["diameter_m"] == pytest.approx(a * math.sqrt(2.0), rel=1e-14)
    # The nearest pair is a side: a minus two radii.
    assert e["d_min_m"] == pytest.approx(a - 0.5, rel=1e-14)
    # m_i = a/2; M = (a sqrt 2 + a) / 2; L = 4 (a/2)^3 / M^3 = 4 / (sqrt 2 + 1)^3.
    assert e["uniformity_l"] == pytest.approx(4.0 / (math.sqrt(2.0) + 1.0) ** 3, rel=1e-14)
    # Radii per satellite: the gap of the side between satellites 0 and 1 is the smallest.
    e = satflock.characterize(square, radii=[1.0, 0.5, 0.0, 0.0])
    assert e["d_min_m"] == pytest.approx(a - 1.5, rel=1e-14)


def test_points_on_a_line_far_from_the_origin():
    # x = 0, 1, 3 m, offset by an EME2000-sized position: frame-invariant elements are unchanged.
    offset = np.array([7.0e6, -1.0e6, 2.0e5])
    line = np.array([[0, 0, 0], [1, 0, 0], [3, 0, 0]], dtype=float) + offset
    e = satflock.characterize(line)
    np.testing.assert_allclose(e["r_o_m"], offset + [4.0 / 3.0, 0, 0], rtol=1e-15)
    assert e["d_max_m"] == pytest.approx(5.0 / 3.0, rel=1e-9)
    assert e["diameter_m"] == pytest.approx(3.0, rel=1e-9)
    assert e["d_min_m"] == pytest.approx(1.0, rel=1e-9)
    # m = (0.5, 0.5, 1); M = max(1 + 1, 3 + 1.5, 2 + 1.5) / 2 = 2.25; L = 1.25 / 2.25^3.
    assert e["uniformity_l"] == pytest.approx(1.25 / 2.25**3, rel=1e-9)


def test_lists_are_accepted():
    e = satflock.characterize([[0, 0, 0], [0, 0, 2]])
    assert e["diameter_m"] == 2.0 and e["d_min_m"] == 2.0 and e["d_max_m"] == 1.0


@pytest.mark.parametrize(
    "kwargs, says",
    [
        (dict(positions=np.zeros((4, 2))), "positions has shape (4, 2)"),
        (dict(positions=np.zeros(3)), "positions has shape (3,)"),
        (dict(positions=np.zeros((1, 3))), "positions has 1 rows"),
        (dict(positions=[[0, 0, 0], [1, np.inf, 0]]), "positions[1]"),
        (dict(positions="abc"), "positions: cannot be read"),
        (dict(positions=np.eye(3), velocities=np.zeros((2, 3))), "velocities has 2 rows"),
        (dict(positions=np.eye(3), velocities=[[0, 0, 0], [0, 0, 0], [np.nan, 0, 0]]), "velocities[2]"),
        (dict(positions=np.eye(3), radii=[1.0, 2.0]), "radii has shape (2,)"),
        (dict(positions=np.eye(3), radii=[1.0, -2.0, 0.0]), "radii[1]"),
        (dict(positions=np.eye(3), radii=float("nan")), "radii:"),
    ],
)
def test_bad_input_names_the_argument(kwargs, says):
    with pytest.raises(ValueError) as info:
        satflock.characterize(**kwargs)
    assert says in str(info.value)

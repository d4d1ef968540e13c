"""The lattice under a trajectory: the disks drawn are the scene's, and every collision of a
trajectory lies on one of them."""

from fractions import Fraction

import numpy as np
import pytest

import lorentz_gas as lg


@pytest.mark.parametrize(
    "kw, r",
    [(dict(w="0.1"), 1.0), (dict(w="1/2"), 1.0), (dict(scene="square", radius="1/4"), 0.25)],
)
def test_every_collision_of_a_trajectory_is_on_a_drawn_disk(kw, r):
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ev = lg.events(n=3000, seed=2, **kw)
    fig, ax = plt.subplots()
    ax.plot(ev["x"], ev["y"], lw=0.5)
    patches = lg.draw_lattice(ax, **kw)
    centres = np.array([p.center for p in patches])
    assert all(p.radius == r for p in patches)
    hits = ev[ev["collision"]]
    d = np.hypot(hits["x"][:, None] - centres[:, 0], hits["y"][:, None] - centres[:, 1]).min(axis=1)
    # Every contact point is on a disk to rounding (positions of size ~100 carry ~1e-13).
    assert np.all(np.abs(d - r) < 1e-10), np.abs(d - r).max()
    # And no drawn disk is far from the box: each reaches into the limits.
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert np.all((centres[:, 0] >= x0 - r) & (centres[:, 0] <= x1 + r))
    assert np.all((centres[:, 1] >= y0 - r) & (centres[:, 1] <= y1 + r))
    plt.close(fig)


def test_the_triangular_disks_are_the_lattice_points():
    disks = lg.lattice_disks("0.1", xlim=(-0.5, 2.2), ylim=(-0.5, 0.5))
    # a = 2.1: the disks at (0, 0) and (2.1, 0), and those of the rows above and below whose
    # disks reach into the box.
    assert (0.0, 0.0, 1.0) in disks and (2.1, 0.0, 1.0) in disks
    assert all(abs(y) <= 0.5 + 1 for _, y, _ in disks)


def test_bad_scenes_are_refused_with_the_range():
    with pytest.raises(ValueError, match="w > 0"):
        lg.lattice_disks("-0.1", xlim=(0, 1), ylim=(0, 1))
    with pytest.raises(ValueError, match="0 < radius < 1/2"):
        lg.lattice_disks(scene="square", radius="1/2", xlim=(0, 1), ylim=(0, 1))
    with pytest.raises(ValueError, match="triangular"):
        lg.lattice_disks(scene="honeycomb", xlim=(0, 1), ylim=(0, 1))


def test_each_arc_of_a_field_trajectory_ends_at_the_next_event():
    """In a field every flight is an arc of radius 1/|B| about ``centre``: its start and the
    next event are both on that circle, and turning the start by ``angle`` about the centre
    lands on the next event (to the rounding of positions of size ~100, 1e-9). Broken on
    purpose (the centre on the other side, ``+ vy/B``), the distances are 2/|B| off."""
    for b in ("1/2", "-3/2"):
        ev = lg.events(w="0.1", n=500, seed=3, field=b)
        a = lg.arcs(ev, field=b)
        B = float(Fraction(b))
        assert len(a) == 500 and np.all(a["radius"] == 1 / abs(B))
        assert np.all(a["sense"] == np.sign(B))
        end = np.hypot(ev["x"][1:] - a["centre_x"], ev["y"][1:] - a["centre_y"])
        assert np.abs(end - a["radius"]).max() < 1e-9
        start = np.arctan2(a["y"] - a["centre_y"], a["x"] - a["centre_x"])
        x = a["centre_x"] + a["radius"] * np.cos(start + a["angle"])
        y = a["centre_y"] + a["radius"] * np.sin(start + a["angle"])
        assert np.abs(np.hypot(x - ev["x"][1:], y - ev["y"][1:])).max() < 1e-9


def test_straight_flights_have_no_circle_and_a_bad_field_is_refused():
    ev = lg.events(w="0.1", n=20)
    a = lg.arcs(ev)
    assert np.all(np.isnan(a["centre_x"])) and np.all(np.isinf(a["radius"]))
    assert np.all(a["sense"] == 0) and np.allclose(a["time"], np.diff(ev["t"]))
    with pytest.raises(ValueError, match="field"):
        lg.arcs(ev, field="1e9")


def test_draw_events_draws_the_arcs_through_every_event():
    matplotlib = pytest.importorskip("matplotlib")
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    ev = lg.events(w="0.1", n=200, seed=1, field="1/2")
    fig, ax = plt.subplots()
    (line,) = lg.draw_events(ax, ev, field="1/2")
    x, y = line.get_data()
    # Every event point is a vertex of the drawn path, and the path stays on the arcs.
    for px, py in zip(ev["x"], ev["y"]):
        assert np.hypot(x - px, y - py).min() < 1e-9
    assert len(x) > len(ev)
    plt.close(fig)

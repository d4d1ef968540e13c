"""The lattice under a trajectory: the disks drawn are the scene's, and every collision of a
trajectory lies on one of them."""

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

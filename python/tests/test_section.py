"""The Poincaré section (`lg.section`, `lorentz section`): the command line's bits, the same
bits at any thread count, the regular islands of w = 0.2, B = 5/2, a field-free section all
diffusing, and bad input refused."""

import json

import numpy as np
import pytest

import lorentz_gas as lg

from test_same_bits import same

# The default classification (2e5 collisions): at 5e4, trajectory 20 of this seed, a sticky one of
# the sea, has not yet left the limit (reach 2.35, 61 at 2e5) and would be called bounded.
ISLANDS = dict(w=0.2, field="5/2", trajectories=32, collisions=500, classify_collisions=200_000,
               seed=3)


def test_section_has_the_command_lines_bits(cli_json):
    py = lg.section(w="0.2", field="5/2", trajectories=8, collisions=200,
                    classify_collisions=20_000, seed=5, threads=2, progress=False)
    cl = cli_json("section", "--w", "0.2", "--field", "5/2", "--trajectories", "8",
                  "--collisions", "200", "--classify-collisions", "20000", "--seed", "5")
    same(py.to_dict(), cl)
    assert py.theta.tobytes() == np.asarray(cl["theta"], dtype=np.float64).tobytes()


def test_the_same_seed_gives_the_same_bits_whatever_the_threads():
    a = lg.section(**ISLANDS, threads=1, progress=False)
    b = lg.section(**ISLANDS, threads=2, progress=False)
    assert a.theta.tobytes() == b.theta.tobytes() and a.p.tobytes() == b.p.tobytes()
    assert list(a.component) == list(b.component)
    assert a.reach.tobytes() == b.reach.tobytes()


def test_islands_at_w_0_2_and_b_5_2_are_bounded_curves():
    r = lg.section(**ISLANDS, progress=False)
    assert r.bounded >= 1, list(r.component)
    assert r.pinned + r.skipping + r.bounded + r.diffusing == 32
    bounded = np.flatnonzero(r.component == "bounded")
    assert np.all(r.reach[bounded] <= r.limit)
    assert np.all(r.reach[r.component == "diffusing"] > r.limit)
    for t in bounded:
        # An island trajectory bounces among the three disks of one trap: its points fill closed
        # curves round three values of theta (a fourth cluster where one wraps round -pi).
        mask = r.trajectory == t
        assert mask.sum() == 500
        assert np.ptp(r.p[mask]) < 1.0
        theta = np.sort(r.theta[mask])
        clusters = 1 + int(np.sum(np.diff(theta) > 0.5))
        assert clusters <= 4, (t, clusters)
    assert np.all(np.abs(r.p) <= 1.0)
    frame = r.to_pandas()
    assert list(frame.columns) == ["trajectory", "component", "disk", "theta", "p"]
    assert len(frame) == len(r.theta)
    assert "bounded" in repr(r) and "islands" in str(r)


def test_without_a_field_every_trajectory_diffuses():
    r = lg.section(w=0.2, trajectories=16, collisions=100, progress=False)
    assert r.diffusing == 16 and r.bounded == r.skipping == r.pinned == 0
    assert r.limit is None and r.field is None
    assert len(r.theta) == 16 * 100


@pytest.mark.parametrize("kwargs, match", [
    (dict(trajectories=0), "trajectories"),
    (dict(collisions=0), "collisions"),
    (dict(collisions=100, classify_collisions=10), "classify_collisions"),
    (dict(trajectories=100_000, collisions=1000), "collisions"),
    (dict(field="x"), "field"),
    (dict(w=-1), "w"),
])
def test_bad_input_raises_value_error(kwargs, match):
    args = dict(w=0.2, field="5/2", trajectories=2, collisions=10, classify_collisions=10)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        lg.section(**args, progress=False)


def test_plot_draws_one_collection_per_component():
    mpl = pytest.importorskip("matplotlib")
    mpl.use("Agg")
    r = lg.section(w=0.2, field="5/2", trajectories=4, collisions=50, classify_collisions=1000,
                   progress=False)
    ax = r.plot()
    assert len(ax.collections) == 3
    assert ax.get_xlim() == (-np.pi, np.pi)
    json.loads(r.to_json())

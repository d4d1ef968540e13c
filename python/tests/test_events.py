"""`events`: dtype and shapes, the kinematics between events, and the mean free path against
Santaló's value."""

import math

import numpy as np

import lorentz_gas as lg


def test_events_dtype_shape_and_kinds():
    ev = lg.events(w="0.1", n=10_000, seed=3)
    assert ev.dtype == lg.EVENT_DTYPE and ev.shape == (10_000,)
    assert ev["collision"].any() and (~ev["collision"]).any()
    assert set(np.unique(ev["obstacle"])) <= {0, 1, 2}
    assert np.all(np.diff(ev["t"]) >= 0)


def test_consecutive_events_are_a_straight_flight_at_unit_speed():
    ev = lg.events(w="0.2", n=20_000, seed=1)
    dt = np.diff(ev["t"])
    dr = np.hypot(np.diff(ev["x"]), np.diff(ev["y"]))
    # The displacement between two events is the flight: |dr| = dt (speed 1) and its direction
    # is the velocity after the earlier event. Rounding: positions of size |x| ~ 10 carry an
    # absolute error of a few ulps of 10 (~1e-14), so the bound is absolute, not relative.
    scale = 1e-12 * (1 + np.maximum(np.abs(ev["x"][1:]), np.abs(ev["y"][1:])))
    assert np.all(np.abs(dr - dt) < scale)
    along = np.diff(ev["x"]) * ev["vx"][:-1] + np.diff(ev["y"]) * ev["vy"][:-1]
    assert np.all(np.abs(along - dt) < scale)
    assert np.allclose(np.hypot(ev["vx"], ev["vy"]), 1.0, atol=1e-14)


def test_the_same_seed_gives_the_same_events_and_another_batch_others():
    a = lg.events(w=0.15, n=1000, seed=2)
    b = lg.events(w="0.15", n=1000, seed=2)
    c = lg.events(w=0.15, n=1000, seed=2, batch=1)
    assert a.tobytes() == b.tobytes()
    assert a["x"][0] != c["x"][0]


def test_the_mean_free_path_from_events_is_santalos():
    w, batches, n = "0.1", 16, 200_000
    per_batch = []
    for b in range(batches):
        ev = lg.events(w=w, n=n, seed=11, batch=b)
        t = ev["t"][ev["collision"]]
        per_batch.append(np.diff(t).mean())
    per_batch = np.array(per_batch)
    mean = per_batch.mean()
    se = per_batch.std(ddof=1) / math.sqrt(batches)
    exact = lg.constants(w).to_dict()["mean_free_path"]
    z = (mean - exact) / se
    # Student-t equivalent of 4 sigma with batches - 1 degrees of freedom.
    assert abs(z) < lg.agreement_bound(batches - 1), (mean, se, exact, z)
    # And the error is honest: not so large that the comparison says nothing.
    assert se < 1e-3 * exact


def test_square_scene_events():
    ev = lg.events(scene="square", radius="1/4", n=5000)
    assert ev.shape == (5000,)
    # Every collision point lies on a disk of radius 1/4 about a lattice point.
    c = ev[ev["collision"]]
    d = np.hypot(c["x"] - np.round(c["x"]), c["y"] - np.round(c["y"]))
    assert np.allclose(d, 0.25, atol=1e-12)


def test_events_beyond_the_horizon_fly_through_the_corridors():
    """At w = 1/2 (infinite horizon) the flights still obey |dr| = dt, and some cross many
    traps: the longest free flight exceeds the finite-horizon bound 12a."""
    ev = lg.events(w="1/2", n=1_000_000, seed=5)
    dt = np.diff(ev["t"])
    dr = np.hypot(np.diff(ev["x"]), np.diff(ev["y"]))
    scale = 1e-12 * (1 + np.maximum(np.abs(ev["x"][1:]), np.abs(ev["y"][1:])))
    assert np.all(np.abs(dr - dt) < scale)
    flights = np.diff(ev["t"][ev["collision"]])
    assert flights.max() > 12 * 2.5

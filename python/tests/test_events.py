"""`events`: dtype and shapes, the kinematics between events, and the mean free path against
Santaló's value."""

import math

import numpy as np
import pytest

import lorentz_gas as lg


def test_events_dtype_shape_and_kinds():
    ev = lg.events(w="0.1", n=10_000, seed=3)
    assert ev.dtype == lg.EVENT_DTYPE and ev.shape == (10_001,)
    # Row 0 is the start: t = 0, no obstacle; then events named by kind.
    start, rest = ev[0], ev[1:]
    assert start["kind"] == "start" and start["t"] == 0 and start["obstacle"] == 255
    assert not start["collision"]
    assert set(np.unique(rest["kind"])) == {"collision", "crossing"}
    assert np.array_equal(rest["kind"] == "collision", rest["collision"])
    assert set(np.unique(rest["obstacle"])) <= {0, 1, 2}
    assert np.all(np.diff(ev["t"]) >= 0) and np.all(rest["t"] > 0)


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
    assert ev.shape == (5001,)
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


def test_events_in_a_field_are_arcs_of_radius_one_over_b():
    b = 1.5
    ev = lg.events(w="0.2", n=20_000, seed=4, field="3/2")
    dt = np.diff(ev["t"])
    dr = np.hypot(np.diff(ev["x"]), np.diff(ev["y"]))
    scale = 1e-12 * (1 + np.maximum(np.abs(ev["x"][1:]), np.abs(ev["y"][1:])))
    # The chord of an arc of angle B·dt on a circle of radius 1/|B|.
    assert np.all(np.abs(dr - 2 * np.sin(b * dt / 2) / b) < scale)
    # Across an edge the velocity only turns: by B·dt, counter-clockwise for B > 0.
    c, s = np.cos(b * dt), np.sin(b * dt)
    vx, vy = ev["vx"][:-1], ev["vy"][:-1]
    turned_x, turned_y = c * vx - s * vy, s * vx + c * vy
    crossing = ~ev["collision"][1:]
    assert crossing.sum() > 1000
    assert np.allclose(turned_x[crossing], ev["vx"][1:][crossing], atol=1e-11)
    assert np.allclose(turned_y[crossing], ev["vy"][1:][crossing], atol=1e-11)
    assert np.allclose(np.hypot(ev["vx"], ev["vy"]), 1.0, atol=1e-13)
    # Broken on purpose, the opposite sense of rotation does not fit.
    assert not np.allclose(c * vx + s * vy, ev["vx"][1:], atol=1e-6)


def test_events_in_a_field_on_the_square_lattice_are_arcs_of_radius_one_over_b():
    b = 1.0
    ev = lg.events(scene="square", radius="1/4", n=20_000, seed=4, field="1")
    dt = np.diff(ev["t"])
    dr = np.hypot(np.diff(ev["x"]), np.diff(ev["y"]))
    scale = 1e-12 * (1 + np.maximum(np.abs(ev["x"][1:]), np.abs(ev["y"][1:])))
    assert np.all(np.abs(dr - 2 * np.sin(b * dt / 2) / b) < scale)
    assert np.allclose(np.hypot(ev["vx"], ev["vy"]), 1.0, atol=1e-13)
    # The start is on a diffusing orbit: the walk leaves its cell (a pinned circle would not).
    assert np.hypot(ev["x"][-1], ev["y"][-1]) > 2


def test_events_with_field_zero_are_the_events_without_a_field():
    a = lg.events(w="0.1", n=2000, seed=5)
    b = lg.events(w="0.1", n=2000, seed=5, field=0)
    assert a.tobytes() == b.tobytes()
    c = lg.events(w="0.1", n=2000, seed=5, field="1/10")
    assert c.tobytes() == lg.events(w="0.1", n=2000, seed=5, field=0.1).tobytes()
    assert c.tobytes() != a.tobytes()


def test_events_in_a_field_refuse_what_has_no_diffusing_orbit():
    import pytest

    with pytest.raises(ValueError, match="every orbit is localized"):
        lg.events(w="0.3", n=10, field=10)
    with pytest.raises(ValueError, match="every orbit is localized"):
        lg.events(scene="square", radius="1/4", n=10, field=4)
    with pytest.raises(ValueError, match="field"):
        lg.events(w="0.1", n=10, field="1/0")


def test_a_trajectory_in_chunks_has_the_bits_of_one_call():
    """Continued call after call, a trajectory gives the events of one call, time included (one
    running sum), with and without a field and on the square lattice."""
    for kw in [dict(w="0.1"), dict(w="0.2", field="-3/2"), dict(scene="square", radius="1/4"),
               dict(scene="square", radius="1/4", field="1"),
               dict(scene="square", radius="1/1000"), dict(w="10")]:
        whole = lg.events(n=5000, seed=7, batch=2, **kw)
        tr = lg.Trajectory(seed=7, batch=2, **kw)
        parts = [tr.start] + [tr.events(k) for k in (1, 999, 2500, 1500)]
        chunked = np.concatenate(parts)
        assert chunked.tobytes() == whole.tobytes(), kw
        assert tr.time == whole["t"][-1]
    # The start row of a trajectory is where its first flight begins: the first event is one
    # flight away at unit speed.
    ev = lg.events(w="0.2", n=1, seed=3)
    assert np.hypot(ev["x"][1] - ev["x"][0], ev["y"][1] - ev["y"][0]) == pytest.approx(ev["t"][1], abs=1e-12)


def test_jumped_events_meet_the_disk_the_walk_meets_first():
    """Square lattice, r = 1/1000 (flights of ~500 cells): from the same start, the jumping
    trajectory's first collision is the walk's — same cell, same disk — at the same time. The
    walk's time sums ~700 crossings, each rounded (≤ 700 · 4u · t ≈ 3e-13 t), the jump's is
    within 2.02u t (`proofs-notes/long-flights.md`); both then meet the disk from entry points
    ~1e-13 apart, an offset the collision time sees divided by the cosine of the incidence
    angle. 1e-9 t leaves that cosine down to ~3e-4 (a chance of ~1e-7 per start)."""
    kw = dict(scene="square", radius="1/1000", seed=5)
    for b in range(12):
        walk = lg.events(n=4000, batch=b, flights="walk", **kw)
        jump = lg.events(n=40, batch=b, flights="jump", **kw)
        assert "jump" not in set(walk["kind"]) and "jump" in set(jump["kind"][1:])
        w, j = walk[walk["collision"]][0], jump[jump["collision"]][0]
        assert (w["i"], w["j"], w["obstacle"]) == (j["i"], j["j"], j["obstacle"]), b
        assert abs(w["t"] - j["t"]) <= 1e-9 * w["t"], (b, w["t"], j["t"])
        assert abs(w["x"] - j["x"]) <= 1e-9 * w["t"] and abs(w["y"] - j["y"]) <= 1e-9 * w["t"]


def test_jumped_events_are_straight_flights_and_give_santalos_mean_free_path():
    batches, n, kw = 16, 20_000, dict(scene="square", radius="1/1000", seed=11)
    per_batch = []
    for b in range(batches):
        ev = lg.events(n=n, batch=b, **kw)
        # A jump row is a straight flight from the row before, like any other: the displacement
        # is the velocity times the flight time. The speed is 1 only within the reflections'
        # rounding, ~u/r per collision (here |v| - 1 reaches ~1e-12, 4e-10 over a flight of
        # ~500), so the time is compared with the distance over |v|. Positions of size
        # |x| ~ 10^4 carry a few ulps of it; t ~ 10^7, a few ulps of its own.
        dt = np.diff(ev["t"])
        dr = np.hypot(np.diff(ev["x"]), np.diff(ev["y"]))
        speed = np.hypot(ev["vx"], ev["vy"])[:-1]
        scale = 1e-12 * (1 + np.maximum(np.abs(ev["x"][1:]), np.abs(ev["y"][1:])))
        assert np.all(np.abs(dr / speed - dt) < scale + 1e-15 * ev["t"][1:])
        jumps = ev[ev["kind"] == "jump"]
        assert len(jumps) > 0 and set(np.unique(jumps["obstacle"])) <= {0, 1, 2, 3}
        per_batch.append(np.diff(ev["t"][ev["collision"]]).mean())
    per_batch = np.array(per_batch)
    mean, se = per_batch.mean(), per_batch.std(ddof=1) / math.sqrt(batches)
    exact = lg.constants(radius="1/1000").to_dict()["mean_free_path"]
    assert abs(mean - exact) < lg.agreement_bound(batches - 1) * se, (mean, se, exact)
    assert se < 2e-2 * exact


def test_which_engine_the_events_run_follows_the_auto_rule():
    assert lg.Trajectory(scene="square", radius="1/4").flights == "walk"
    assert lg.Trajectory(scene="square", radius="1/8").flights == "jump"
    assert lg.Trajectory(scene="square", radius="1/8", flights="walk").flights == "walk"
    assert lg.Trajectory(scene="square", radius="1/4", flights="jump").flights == "jump"
    assert lg.Trajectory(w="4").flights == "walk" and lg.Trajectory(w="6").flights == "jump"
    assert lg.Trajectory(w="0.1").flights == "walk"
    assert lg.Trajectory(scene="square", radius="1/1000", field="1").flights == "walk"
    assert "flights jump" in repr(lg.Trajectory(w="10"))
    for kw, says in [(dict(w="0.1", flights="jump"), "has no long flights"),
                     (dict(w="10", flights="hop"), "use auto, walk or jump"),
                     (dict(w="10", field="1/100", flights="jump"), "cell by cell")]:
        with pytest.raises(ValueError, match=says):
            lg.events(n=10, **kw)

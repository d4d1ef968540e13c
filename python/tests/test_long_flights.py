"""Long flights (`flights=`): the jumps give the command line's bits, say so, and are refused
where they do not apply."""

from fractions import Fraction

import numpy as np
import pytest

import lorentz_gas as lg


def test_lyapunov_with_jumps_has_the_command_lines_bits(cli_json):
    args = dict(scene="square", radius="1/1000", collisions_per_batch=1e5, batches=4, starts=0)
    r = lg.lyapunov(**args, progress=False)
    c = cli_json("lyapunov", "--scene", "square", "--radius", "1/1000",
                 "--collisions-per-batch", "1e5", "--batches", "4", "--starts", "0")
    assert r.tangent["flights"] == c["tangent"]["flights"] == "jump"
    assert r.tangent["per_collision"] == c["tangent"]["per_collision"]
    walk = lg.lyapunov(**args, flights="walk", progress=False)
    assert walk.tangent["flights"] == "walk"


def test_triangular_jumps_beyond_w_inf_have_the_command_lines_bits(cli_json):
    r = lg.lyapunov(w=100, collisions_per_batch=1e4, batches=4, starts=0, progress=False)
    c = cli_json("lyapunov", "--w", "100", "--collisions-per-batch", "1e4", "--batches", "4",
                 "--starts", "0")
    assert r.tangent["flights"] == c["tangent"]["flights"] == "jump"
    assert r.tangent["per_collision"] == c["tangent"]["per_collision"]
    a = lg.audit(w=100, collisions=400, batches=2, progress=False)
    t = a.summary["triangular_jumps"]
    assert a.flights == "jump" and t["audited"] >= 300 and t["outside"] == 0


@pytest.mark.parametrize("kw, says", [
    (dict(w=0.1, flights="jump"), "has no long flights"),
    (dict(w=0.1, flights="hop"), "use auto, walk or jump"),
    (dict(w=0.1, field=1, flights="jump"), "cell by cell"),
])
def test_jumps_where_they_do_not_apply_are_a_value_error(kw, says):
    with pytest.raises(ValueError, match=says):
        lg.lyapunov(**kw, starts=0, progress=False)


def test_audit_replays_the_jumps_with_the_command_lines_bits(cli_json):
    args = dict(scene="square", radius="1/1000", collisions=4000, batches=2)
    r = lg.audit(**args, progress=False)
    c = cli_json("audit", "--scene", "square", "--radius", "1/1000",
                 "--collisions", "4000", "--batches", "2")
    j = r.summary["jumps"]
    assert r.flights == c["flights"] == "jump"
    assert j["audited"] >= 3900 and j["outside"] == 0
    assert j["columns"] == c["summary"]["jumps"]["columns"]
    assert "jumps replayed, 0 outside" in repr(r)
    walk = lg.audit(**args, flights="walk", progress=False)
    assert walk.flights == "walk" and walk.summary["jumps"]["audited"] == 0
    with pytest.raises(ValueError, match="cell by cell"):
        lg.audit(**args, field=1, flights="jump", progress=False)


def test_superdiffusion_jumps_by_default_with_the_command_lines_bits(cli_json):
    args = dict(scene="square", radius="1/100", collisions=32000, batches=16, octaves=4)
    r = lg.superdiffusion(**args, progress=False)
    c = cli_json("superdiffusion", "--scene", "square", "--radius", "1/100",
                 "--collisions", "32000", "--batches", "16", "--octaves", "4")
    assert r.flights == c["flights"] == "jump"
    assert r.longest_flight == c["longest_flight"]
    walk = lg.superdiffusion(**args, flights="walk", progress=False)
    assert walk.flights == "walk"
    # Beyond w_inf the triangular lattice jumps too (`auto` from w = 6, `jump` at any w).
    tri = lg.superdiffusion(w=0.5, collisions=32000, batches=16, octaves=4, flights="jump",
                            progress=False)
    assert tri.flights == "jump"


def test_bench_times_long_flights_like_the_command_line():
    r = lg.bench(long_flights=["1/4", Fraction(1, 100)], collisions_per_radius=2e4,
                 walk_collisions=200, repetitions=1, progress=False)
    assert list(r.rows["radius"]) == ["1/4", "1/100"]
    assert r.rows["over_first"][0] == 1.0 and np.all(r.rows["ns_per_collision"] > 0)
    assert np.all(r.rows["walk_over_jump"] > 0) and "long flights jumped" in repr(r)
    with pytest.raises(ValueError, match="threads"):
        lg.bench(long_flights=["1/4"], threads=2)
    with pytest.raises(ValueError, match="2\\^-32 <= r <= 1/4|radius"):
        lg.bench(long_flights=["1/2"])
    with pytest.raises(ValueError, match="long_flights= only"):
        lg.bench(w="0.1", walk_collisions=10)
    with pytest.raises(ValueError, match="long_flights= only"):
        lg.bench(w="0.1", scene="triangular")


def test_bench_times_triangular_long_flights_beyond_w_inf(cli_json):
    args = dict(collisions_per_radius=2e4, walk_collisions=200, repetitions=1, progress=False)
    r = lg.bench(long_flights=["10", 100], scene="triangular", **args)
    assert list(r.rows["w"]) == ["10", "100"] and "radius" not in r.rows.dtype.names
    assert r.to_dict()["config"]["gaps"] == ["10", "100"]
    # Santaló's mean free path in disk radii, as `constants` gives it.
    assert r.rows["mean_free_path"][1] == lg.constants(w=100).to_dict()["mean_free_path"]
    assert str(r).splitlines()[0].startswith("long flights, triangular lattice, 1 thread:")
    assert str(r).splitlines()[1].startswith("w ") and "w = 10:" in repr(r)
    c = cli_json("bench", "--scene", "triangular", "--long-flights", "10,100",
                 "--collisions-per-radius", "2e4", "--walk-collisions", "200", "--repetitions", "1")
    assert c["config"] == r.to_dict()["config"]
    assert [row["w"] for row in c["rows"]] == ["10", "100"]
    with pytest.raises(ValueError, match="w_inf = 4/sqrt\\(3\\) - 2 < w"):
        lg.bench(long_flights=["0.2"], scene="triangular")
    with pytest.raises(ValueError, match="use square or triangular"):
        lg.bench(long_flights=["1/4"], scene="hexagonal")


def test_str_of_a_bench_is_the_command_lines_text_shape():
    r = lg.bench(long_flights=["1/4", "1/100"], collisions_per_radius=1e4, walk_collisions=100,
                 repetitions=1, progress=False)
    lines = str(r).splitlines()
    assert lines[0].startswith("long flights, square lattice, 1 thread: 10000 collisions jumping")
    assert lines[2].startswith("1/4 ") and lines[3].startswith("1/100 ")
    b = lg.bench(w="0.1", collisions_per_thread=1e4, repetitions=1, progress=False)
    assert str(b).startswith("w = 0.1  precision f64  engine ")

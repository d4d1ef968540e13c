"""The driven gas from Python: ``diffusion(electric=...)`` has the command line's bits and its
result reads like the others."""

import numpy as np
import pytest

import lorentz_gas as lg

from test_same_bits import same


def test_a_run_under_the_thermostat_has_the_command_lines_bits(cli_json):
    args = dict(w="1/5", electric="3/10", electric_angle="-45", collisions=400_000, batches=4,
                seed=5)
    py = lg.diffusion(**args)
    same(py.to_dict(), cli_json("diffusion", *[x for k, v in args.items()
                                               for x in ("--" + k.replace("_", "-"), str(v))]))
    assert isinstance(py, lg.CurrentResult)
    assert "J/E" in repr(py) and "E = 0.3" in repr(py)
    assert str(py).startswith("periodic Lorentz gas under a thermostatted electric field")
    # The direction of the exact angle −45°: π/4 and its cosine and sine rounded, then
    # normalised, a few units in the last place of √½ (4.4e-16 is four).
    assert np.allclose(py.direction, [np.sqrt(0.5), -np.sqrt(0.5)], rtol=0, atol=4.4e-16)
    angles = py.to_pandas("angles")
    assert len(angles) == len(py.angle_bins) == 72
    # A density per radian: it integrates to 1 over the circle.
    assert abs(np.sum(py.angle_density) * 2 * np.pi / 72 - 1) < 1e-12
    assert len(py.to_pandas("batches")) == 4



def test_a_driven_result_passes_the_publication_audit(tmp_path):
    """``report`` audits a driven result: its record, the sum rule, J_perp = 0 on a mirror line,
    a shadow audit of thermostatted events, a batch re-run to the bit."""
    r = lg.diffusion(w="0.2", electric="3/10", collisions=2e5, batches=8, seed=5)
    rep = lg.report(r, out=tmp_path / "j", quick=True)
    assert rep.verdict == "PASS", [c for c in rep.checks if c["verdict"] not in ("PASS", "N/A")]
    names = [c["name"] for c in rep.checks if c["verdict"] == "PASS"]
    for name in ("sum rule: ", "no current across", "shadow audit of thermostatted events",
                 "the recorded configuration re-run"):
        assert any(n.startswith(name) for n in names), name

def test_a_zero_electric_field_is_the_run_without_a_field():
    a = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3)
    b = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3, electric="0", electric_angle=30)
    assert isinstance(b, lg.DiffusionResult) and list(a.batch_D) == list(b.batch_D)


# Each analysis with the smallest valid run, the bad input given on top of it.
BASE = {
    "diffusion": dict(w="0.2", collisions=2e5, batches=4),
    "sweep": dict(w="0.2", collisions_per_run=2e5, batches_per_run=4),
    "lyapunov": dict(w="0.2", collisions_per_batch=2e3, batches=2),
    "trajectory": dict(start=("0", "1.05"), direction=("1", "1/3"), time="2", w="1/10"),
    "bench": dict(w="0.2", collisions_per_thread=1e4, repetitions=1, engine="scalar"),
}


@pytest.mark.parametrize("call, kwargs, message", [
    ("diffusion", dict(electric="11"), r"0 < \|E\| <= 10"),
    ("diffusion", dict(electric="1", electric_angle="400"), "-360 to 360"),
    ("diffusion", dict(electric="x"), "electric"),
    ("diffusion", dict(electric="1", field="1"), "one motion|both"),
    ("diffusion", dict(electric="1", scene="square", radius="1/4", w=None), "corridor|horizon"),
    ("sweep", dict(electric=["1/10"], fields=["1"]), "fields: a sweep of the driven gas"),
    ("sweep", dict(electric=["1/10"], w=None), "w: a sweep of the driven gas needs its gap"),
    ("sweep", dict(electric="1/10"), "non-empty sequence"),
    ("sweep", dict(electric=["0"]), r"0 < \|E\| <= 10"),
    ("sweep", dict(electric=["1/10"], runs=2), "runs is not used"),
    ("lyapunov", dict(electric="11"), r"0 < \|E\| <= 10"),
    ("lyapunov", dict(electric="1", electric_angle="-361"), "-360 to 360"),
    ("lyapunov", dict(electric="one"), "electric"),
    ("lyapunov", dict(electric_angle="30"), "electric_angle without electric"),
    ("lyapunov", dict(electric="1", field="1"), "one motion"),
    ("lyapunov", dict(electric="1", starts=4), "not measured under the thermostat"),
    ("trajectory", dict(electric="11"), r"0 < \|E\| <= 10"),
    ("trajectory", dict(electric="1", electric_angle="400"), "-360 to 360"),
    ("trajectory", dict(electric_angle="30"), "electric_angle without electric"),
    ("trajectory", dict(electric="1", field="1"), "one motion"),
    ("bench", dict(electric="1", electric_angle="1/0"), "divides by zero"),
    ("bench", dict(electric_angle="45"), "electric_angle without electric"),
])
def test_bad_fields_are_value_errors(call, kwargs, message):
    args = dict(BASE[call], **kwargs)
    if args.get("w") is None:
        args.pop("w")
    with pytest.raises(ValueError, match=message):
        getattr(lg, call)(**args)


def test_a_driven_sweep_has_the_command_lines_bits_and_reads_back(cli_json, tmp_path):
    fields = ["-3/10", "1/10", "3/10"]
    py = lg.sweep(w="1/5", electric=fields, collisions_per_run=3e5, batches_per_run=8, seed=4,
                  threads=2)
    out = tmp_path / "driven"
    cli = cli_json("sweep", "--w", "1/5", "--electric=" + ",".join(fields),
                   "--collisions-per-run", "3e5", "--batches-per-run", "8", "--seed", "4",
                   "--threads", "1", "--out", str(out))
    same(py.to_dict(), cli)
    assert isinstance(py, lg.DrivenSweepResult)
    assert list(py.rows["electric"]) == [-0.3, 0.1, 0.3]
    assert "mobility" in py.to_pandas().columns and len(py.to_pandas("odd")) == 1
    assert str(py).startswith("sweep of the driven gas")
    assert "J(-E) = -J(E) at 1 |E|" in repr(py)
    back = lg.load(str(out))
    assert isinstance(back, lg.DrivenSweepResult)
    assert back.to_dict()["rows"] == py.to_dict()["rows"]




def test_the_thermostat_is_benched_beside_straight_flights():
    r = lg.bench(w="1/5", electric="3/10", collisions_per_thread=2e4, repetitions=2,
                 engine="scalar")
    assert isinstance(r, lg.BenchResult)
    assert r.electric == 0.3 and len(r.samples) == len(r.straight_samples) == 2
    assert 0 < r.thermostat_over_straight < 1
    assert str(r).startswith("w = 0.2  E = 0.3 at 0° from x")
    # The exact angle, as diffusion takes it: 90° is the y axis to the bit.
    up = lg.bench(w="1/5", electric="3/10", electric_angle=90, collisions_per_thread=1e4,
                  repetitions=1, engine="scalar")
    assert up.electric_angle == "90" and list(up.direction) == [0.0, 1.0]
    with pytest.raises(ValueError, match="bare"):
        lg.bench(w="1/5", electric="3/10", collisions_per_thread=2e4, repetitions=1,
                 observe="msd")


def test_the_thermostats_winner_only_floor_is_the_command_lines_tape(cli_json):
    """``bench(electric=..., oracle_floor=True)`` times the winner-only floor on the tape the
    command line records: the same events, found again identically as often."""
    r = lg.bench(w="1/5", electric="3/10", collisions_per_thread=4000, repetitions=2,
                 engine="scalar", oracle_floor=True, progress=False)
    o = r.oracle
    assert o["collisions"] == 4000 and o["events"] > 4000
    # Each repetition's floor rate over its straight flights' (one thread): the median of two.
    over = [1e9 / f / s for f, s in zip(o["samples"], r.straight_samples)]
    assert o["floor_over_straight"] == pytest.approx(sum(over) / 2)
    cl = cli_json("bench", "--w", "1/5", "--electric", "3/10", "--collisions-per-thread", "4000",
                  "--repetitions", "2", "--engine", "scalar", "--oracle-floor")
    assert [cl["oracle"][k] for k in ("events", "identical")] == [o["events"], o["identical"]]


def test_the_driven_pair_has_the_command_lines_bits(cli_json):
    """``lyapunov(electric=...)`` is ``lorentz lyapunov --electric``: the same bits, the sum rule
    within its bounds, a readable repr."""
    args = dict(w="1/5", electric="1/2", electric_angle="30", collisions_per_batch=20000,
                batches=4, seed=3)
    py = lg.lyapunov(**args)
    same(py.to_dict(), cli_json("lyapunov", *[x for k, v in args.items()
                                              for x in ("--" + k.replace("_", "-"), str(v))]))
    assert isinstance(py, lg.LyapunovResult)
    assert str(py).startswith("triangular w=0.2 under E = 0.5 at 30°")
    assert "lambda+" in repr(py) and "Kaplan-Yorke" in repr(py)
    assert abs(py.sum_rule["z"]) <= py.sum_rule["bound"]
    assert py.sum_rule_residual <= py.sum_rule_residual_bound
    assert py.lambda_plus > 0 > py.lambda_minus and 2 < py.kaplan_yorke < 3


def test_a_driven_trajectory_has_the_command_lines_digits(cli_json):
    """``trajectory(electric=..., electric_angle=...)`` certifies the command line's digits, and
    ``electric=0`` is the straight trajectory."""
    kw = dict(start=("0", "1.05"), direction=("1", "1/3"), time="20", w="1/10", digits=30)
    py = lg.trajectory(**kw, electric="3/10", electric_angle=30)
    cl = cli_json("trajectory", "--scene", "triangular", "--w", "1/10", "--start", "0,1.05",
                  "--direction", "1,1/3", "--time", "20", "--digits", "30", "--electric", "3/10",
                  "--electric-angle", "30")
    assert (py.x, py.y, py.distance) == (cl["x"], cl["y"], cl["distance"])
    assert py.electric == "3/10" and py.certified_digits >= 30
    straight = lg.trajectory(**kw)
    assert lg.trajectory(**kw, electric=0, electric_angle=45).to_dict()["x"] == straight.x

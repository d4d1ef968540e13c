"""The same parameters and seed give the same bits in Python and in the command line."""

import json

import numpy as np
import pytest

import lorentz_gas as lg

# Keys that say how long a run took or how it was launched: everything else must be equal.
TIMING = {"seconds", "collisions_per_second", "meta"}


def same(a, b, path=""):
    """Every number equal to the bit (JSON numbers are parsed as the same doubles)."""
    if isinstance(a, dict):
        assert set(a) == set(b), f"{path}: keys differ: {set(a) ^ set(b)}"
        for k in a:
            if k not in TIMING and not k.endswith("seconds"):
                same(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        assert len(a) == len(b), f"{path}: lengths differ"
        for i, (x, y) in enumerate(zip(a, b)):
            same(x, y, f"{path}[{i}]")
    else:
        assert a == b, f"{path}: {a!r} (Python) != {b!r} (command line)"


def test_diffusion_has_the_command_lines_bits(cli_json):
    py = lg.diffusion(w="0.1", collisions=4e6, batches=8, seed=7, threads=2)
    cl = cli_json("diffusion", "--w", "0.1", "--collisions", "4e6", "--batches", "8", "--seed", "7")
    same(py.to_dict(), cl)
    assert py.D == cl["D"] and py.D_err == cl["D_err"]
    assert py.D.hex() == float(cl["D"]).hex()


def test_diffusion_bits_do_not_depend_on_threads_engine_or_how_w_is_written():
    a = lg.diffusion(w=0.1, collisions=2e6, batches=4, threads=1, engine="scalar")
    b = lg.diffusion(w="1/10", collisions="2e6", batches=4, threads=2, engine="auto")
    assert a.D == b.D and list(a.batch_D) == list(b.batch_D)


def test_a_field_run_has_the_command_lines_bits(cli_json):
    py = lg.diffusion(w="0.2", field="-3/2", collisions=2e6, batches=4, seed=7,
                      localization_samples=20000)
    cl = cli_json("diffusion", "--w", "0.2", "--field", "-3/2", "--collisions", "2e6",
                  "--batches", "4", "--seed", "7", "--localization-samples", "20000")
    same(py.to_dict(), cl)
    assert isinstance(py, lg.FieldResult) and "D_xy" in repr(py)
    assert py.field == -1.5 and py.diffusing["D_xy"] == cl["diffusing"]["D_xy"]


def test_a_field_runs_bits_do_not_depend_on_the_engine_or_threads(cli_json):
    # Python on the scalar arc kernel against the command line on the SIMD arc engine (three
    # threads: blocks of 2, 2 and 1 batches).
    py = lg.diffusion(w="0.3", field="7/4", collisions=1e6, batches=5, seed=3, threads=1,
                      engine="scalar", localization_samples=20000)
    cl = cli_json("diffusion", "--w", "0.3", "--field", "7/4", "--collisions", "1e6",
                  "--batches", "5", "--seed", "3", "--threads", "3", "--engine", "simd",
                  "--localization-samples", "20000")
    same(py.to_dict(), cl)
    assert py.to_dict()["meta"]["engine"] == "scalar" and cl["meta"]["engine"] == "simd"


def test_the_square_lattice_in_a_field_has_the_command_lines_bits(cli_json):
    py = lg.diffusion(scene="square", radius="1/4", field="1", collisions=1e6, batches=4,
                      localization_samples=20000)
    cl = cli_json("diffusion", "--scene", "square", "--radius", "1/4", "--field", "1",
                  "--collisions", "1e6", "--batches", "4", "--localization-samples", "20000")
    same(py.to_dict(), cl)
    assert py.radius == 0.25 and "w" not in py.to_dict() and "radius = 0.25" in repr(py)
    # Without a field the square lattice's corridors leave no diffusion coefficient.
    with pytest.raises(ValueError, match="in a magnetic field every scene has a finite horizon"):
        lg.diffusion(scene="square", radius="1/4", collisions=1e6, batches=4)


def test_a_zero_field_is_the_run_without_a_field():
    a = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3)
    b = lg.diffusion(w="0.1", collisions=2e6, batches=4, seed=3, field="0")
    assert isinstance(b, lg.DiffusionResult) and a.D == b.D and list(a.batch_D) == list(b.batch_D)


def test_hops_has_the_command_lines_bits(cli_json):
    py = lg.hops(w=0.2, collisions=2e6, batches=4, order=3, seed=3)
    cl = cli_json("hops", "--w", "0.2", "--collisions", "2e6", "--batches", "4", "--order", "3", "--seed", "3")
    same(py.to_dict(), cl)


def test_theory_and_lattice_walks_have_the_command_lines_bits(cli_json):
    args = ["--w", "0.2", "--collisions", "2e6", "--batches", "4", "--order", "3", "--seed", "3"]
    py = lg.theory(w=0.2, collisions=2e6, batches=4, order=3, seed=3)
    same(py.to_dict(), cli_json("theory", *args))
    assert "D_1" in repr(py)
    py = lg.lattice_walk(w=0.2, collisions=2e6, batches=4, order=3, seed=3)
    same(py.to_dict(), cli_json("lattice-walk", *args))


def test_sweep_has_the_command_lines_bits(cli_json, tmp_path):
    py = lg.sweep(w_from="0.1", w_to="0.2", steps=2, runs=2, collisions_per_run=1e6, batches_per_run=2, seed=5)
    cl = cli_json(
        "sweep", "--w-from", "0.1", "--w-to", "0.2", "--steps", "2", "--runs", "2",
        "--collisions-per-run", "1e6", "--batches-per-run", "2", "--seed", "5",
        "--out", str(tmp_path / "sweep"),
    )
    same(py.to_dict(), cl)
    assert list(py.D) == [r["D"] for r in cl["rows"]]


def test_a_square_lattice_sweep_over_b_has_the_command_lines_bits(cli_json, tmp_path):
    py = lg.sweep(scene="square", radius="1/4", fields=["-1", "1", "4"], collisions_per_run=4e5,
                  batches_per_run=4, localization_samples=1000)
    cl = cli_json(
        "sweep", "--scene", "square", "--radius", "1/4", "--fields=-1,1,4",
        "--collisions-per-run", "4e5", "--batches-per-run", "4", "--localization-samples", "1000",
        "--out", str(tmp_path / "sweep"),
    )
    same(py.to_dict(), cl)
    assert list(py.radius) == [0.25] * 3 and "w" not in py.rows.dtype.names
    # B = 4: every orbit localized (2/B <= 1 - 2r), D = 0 and no collision (mean free time inf).
    assert bool(py.all_localized[2]) and py.D_xx[2] == 0.0 and np.isnan(py.mean_free_time[2])
    with pytest.raises(ValueError, match="triangular scene's"):
        lg.sweep(w_from="0.1", w_to="0.2", scene="square", radius="1/4")
    with pytest.raises(ValueError, match="the square scene needs radius="):
        lg.sweep(scene="square", fields=[1])


def test_a_sweep_in_a_field_has_the_command_lines_bits(cli_json, tmp_path):
    # Python on the scalar arc kernel, the command line on the SIMD arc engine.
    py = lg.sweep(w="0.1", fields=["-1", "1/2"], collisions_per_run=1e6, batches_per_run=4,
                  seed=5, localization_samples=1000, engine="scalar")
    cl = cli_json(
        "sweep", "--w", "0.1", "--fields=-1,1/2", "--collisions-per-run", "1e6",
        "--batches-per-run", "4", "--seed", "5", "--localization-samples", "1000",
        "--out", str(tmp_path / "sweep"), "--engine", "simd",
    )
    same(py.to_dict(), cl)
    assert list(py.field) == [-1.0, 0.5] and list(py.D_xx) == [r["D_xx"] for r in cl["rows"]]
    assert py.to_pandas().shape[0] == 2 and "points in a field" in repr(py)
    with pytest.raises(ValueError, match="runs is not used"):
        lg.sweep(w="0.1", fields=[1], runs=2)
    with pytest.raises(ValueError, match="not both"):
        lg.sweep(w="0.1", w_from="0.1", w_to="0.2", field=1)
    with pytest.raises(ValueError, match="field"):
        lg.sweep(w="0.1", fields=[0, 1])


def test_lyapunov_and_trajectory_in_a_field_have_the_command_lines_bits(cli_json):
    py = lg.lyapunov(w="0.1", field="1/2", collisions_per_batch=2e4, batches=4, seed=3)
    cl = cli_json("lyapunov", "--scene", "triangular", "--w", "0.1", "--field", "1/2",
                  "--collisions-per-batch", "2e4", "--batches", "4", "--seed", "3")
    same(py.to_dict(), cl)
    assert py.field == 0.5 and "per collision" in repr(py)
    with pytest.raises(ValueError, match="not measured in a field"):
        lg.lyapunov(w="0.1", field=1, starts=4)
    py = lg.lyapunov(scene="square", radius="1/4", field="-1", collisions_per_batch=2e4,
                     batches=4, seed=3)
    cl = cli_json("lyapunov", "--scene", "square", "--radius", "1/4", "--field", "-1",
                  "--collisions-per-batch", "2e4", "--batches", "4", "--seed", "3")
    same(py.to_dict(), cl)
    assert py.to_dict()["tangent"]["scene"].startswith("square")
    py = lg.trajectory(start=("1.05", "0"), direction=(0, 1), time=10, w="0.1", field=1, digits=30)
    cl = cli_json("trajectory", "--scene", "triangular", "--w", "0.1", "--start", "1.05,0",
                  "--direction", "0,1", "--time", "10", "--field", "1", "--digits", "30")
    same(py.to_dict(), cl)
    assert py.x.startswith("-1.0118118113794999046328468617925") and py.field == "1"


def test_trajectory_has_the_command_lines_digits(cli_json):
    py = lg.trajectory(start=("21/20", "3/5"), direction=(1, "1/3"), time=10, w="0.1", digits=25)
    cl = cli_json("trajectory", "--scene", "triangular", "--w", "0.1", "--start", "21/20,3/5",
                  "--direction", "1,1/3", "--time", "10", "--digits", "25")
    same(py.to_dict(), cl)
    assert isinstance(py.x, str) and py.x == cl["x"]


def test_constants_are_the_command_lines(cli):
    code, out, _ = cli("constants", "--w", "1/7", "--precision", "200", "--json")
    assert code == 0
    py = json.loads(lg.constants("1/7", precision=200).to_json())
    cl = json.loads(out)
    py.pop("meta"), cl.pop("meta")
    assert py == cl
    # Every digit of the working precision is kept in the JSON text, not just a double's.
    assert '"w_exact": "1/7"' in lg.constants("1/7", precision=200).to_json()


def test_every_other_analysis_has_the_command_lines_bits(cli_json):
    """Backscatter, escape, Lyapunov, audit, certify and shadow at small statistics: every
    number equal, not just the keys."""
    cases = [
        (lambda: lg.backscatter(w="0.1", particles=1e5, batches=4, seed=2),
         ["backscatter", "--w", "0.1", "--particles", "1e5", "--batches", "4", "--seed", "2"]),
        (lambda: lg.escape(w="0.2", particles_per_width=4e3, seed=2),
         ["escape", "--w", "0.2", "--particles-per-width", "4e3", "--seed", "2"]),
        (lambda: lg.lyapunov(w="0.2", collisions_per_batch=1e4, batches=4, starts=0, seed=2),
         ["lyapunov", "--scene", "triangular", "--w", "0.2", "--collisions-per-batch", "1e4",
          "--batches", "4", "--starts", "0", "--seed", "2"]),
        (lambda: lg.audit(scene="square", radius="1/3", collisions=2e3, batches=2, seed=2),
         ["audit", "--scene", "square", "--radius", "1/3", "--collisions", "2e3", "--batches", "2",
          "--seed", "2"]),
        (lambda: lg.audit(w="0.1", field="-3/2", collisions=2e3, batches=2, seed=2),
         ["audit", "--w", "0.1", "--field", "-3/2", "--collisions", "2e3", "--batches", "2",
          "--seed", "2"]),
        (lambda: lg.certify(w="0.2", collisions=50, digits=10, seed=2),
         ["certify", "--scene", "triangular", "--w", "0.2", "--collisions", "50", "--digits", "10",
          "--seed", "2"]),
        (lambda: lg.shadow(w="0.2", collisions_per_segment=20, segments=2, seed=2),
         ["shadow", "--w", "0.2", "--collisions-per-segment", "20", "--segments", "2", "--seed", "2"]),
        (lambda: lg.shadow(w="0.2", collisions_per_segment=20, segments=2, seed=2, field="-1/2"),
         ["shadow", "--w", "0.2", "--collisions-per-segment", "20", "--segments", "2", "--seed", "2",
          "--field", "-1/2"]),
        (lambda: lg.shadow(scene="square", radius="1/4", collisions_per_segment=20, segments=2,
                           seed=2, field="1"),
         ["shadow", "--scene", "square", "--radius", "1/4", "--collisions-per-segment", "20",
          "--segments", "2", "--seed", "2", "--field", "1"]),
        (lambda: lg.shadow(w="0.2", collisions_per_segment=20, segments=2, seed=2,
                           electric="3/10", electric_angle=30),
         ["shadow", "--w", "0.2", "--collisions-per-segment", "20", "--segments", "2", "--seed", "2",
          "--electric", "3/10", "--electric-angle", "30"]),
    ]
    for run, args in cases:
        same(run().to_dict(), cli_json(*args), args[0])


def test_constants_of_the_square_lattice_and_beyond_w_inf_are_the_command_lines(cli):
    for py, args in [
        (lg.constants(radius="1/4"), ["--scene", "square", "--radius", "1/4"]),
        (lg.constants("0.35"), ["--w", "0.35"]),
    ]:
        code, out, err = cli("constants", *args, "--json")
        assert code == 0, err
        cl = json.loads(out)
        d = json.loads(py.to_json())
        d.pop("meta"), cl.pop("meta")
        assert d == cl
    sd = lg.constants(radius="1/4").superdiffusion
    assert len(sd["corridors"]) == 4 and sd["msd_r_t_ln_t"] == 2 * sd["C_flow"]


def test_superdiffusion_has_the_command_lines_bits(cli_json):
    py = lg.superdiffusion(radius="1/4", scene="square", collisions=3.2e6, batches=16, octaves=6,
                           vacf_fit=(8, 32), msd_fit=(16, 64), seed=4)
    cl = cli_json("superdiffusion", "--scene", "square", "--radius", "1/4", "--collisions", "3.2e6",
                  "--batches", "16", "--octaves", "6", "--vacf-fit", "8:32", "--msd-fit", "16:64",
                  "--seed", "4")
    same(py.to_dict(), cl)
    assert list(py.lags["t_c"]) == [r["t_c"] for r in cl["lags"]]
    assert py.D_sup_exact == cl["D_sup_exact"] and len(py.corridors) == 4


def test_a_planned_run_has_the_command_lines_bits_and_plan(cli_json):
    py = lg.diffusion(w="0.2", rel_err=2e-3, collisions=4e6, batches=8, seed=3)
    cl = cli_json("diffusion", "--w", "0.2", "--rel-err", "2e-3", "--collisions", "4e6",
                  "--batches", "8", "--seed", "3")
    same(py.to_dict(), cl)
    assert py.pilot["rel_err_target"] == 2e-3 and py.collisions == py.pilot["planned_collisions"]
    pilot = lg.diffusion(w="0.2", collisions=4e6, batches=8, seed=3)
    # Python's planner is the library's: the pilot's own plan for the target is the run's size.
    assert pilot.collisions_for(2e-3) == py.pilot["planned_collisions"] > 4e6
    assert pilot.D_err / pilot.D == py.pilot["rel_err"]
    with pytest.raises(ValueError, match=r"\[1e-7, 0.5\]"):
        pilot.collisions_for(0.7)
    with pytest.raises(ValueError, match=r"\[1e-7, 0.5\]"):
        lg.diffusion(w="0.2", rel_err=0.0)


class _Stages:
    """A progress callable with ``restart``: what it was told, in order."""

    def __init__(self):
        self.calls = []

    def __call__(self, n):
        self.calls.append(("done", n))

    def restart(self, total):
        self.calls.append(("restart", total))


def test_a_planned_runs_progress_starts_again_over_the_planned_collisions():
    stages = _Stages()
    r = lg.diffusion(w="0.2", rel_err=2e-3, collisions=4e6, batches=8, seed=3, progress=stages)
    restarts = [k for k, (what, _) in enumerate(stages.calls) if what == "restart"]
    assert len(restarts) == 1
    k = restarts[0]
    # The pilot's collisions, then the planned run's over the total announced (the pilot's
    # trajectories it continues are counted there, as the command line's second bar counts them).
    assert sum(n for _, n in stages.calls[:k]) == 4e6
    assert stages.calls[k][1] == r.collisions == r.pilot["planned_collisions"]
    assert sum(n for _, n in stages.calls[k + 1:]) == r.collisions


def test_the_plan_alone_is_the_command_lines_pilot_with_its_plan(cli_json):
    py = lg.diffusion(w="0.2", rel_err=2e-3, plan_only=True, collisions=4e6, batches=8, seed=3)
    cl = cli_json("diffusion", "--w", "0.2", "--rel-err", "2e-3", "--plan-only", "--collisions",
                  "4e6", "--batches", "8", "--seed", "3")
    same(py.to_dict(), cl)
    assert py.collisions == 4e6 and py.pilot["continued"] is False
    assert py.plan["rel_err"] == 2e-3 and py.plan["collisions"] == py.pilot["planned_collisions"]
    planned = lg.diffusion(w="0.2", rel_err=2e-3, collisions=4e6, batches=8, seed=3)
    assert planned.collisions == py.plan["collisions"] and planned.pilot["continued"] is True
    with pytest.raises(ValueError, match="give rel_err too"):
        lg.diffusion(w="0.2", plan_only=True)


def test_bench_has_the_command_lines_keys_and_counts(cli_json):
    py = lg.bench(w="0.2", collisions_per_thread=2e5, repetitions=3, progress=False)
    cl = cli_json("bench", "--w", "0.2", "--collisions-per-thread", "2e5", "--repetitions", "3")
    assert py.keys() == list(cl)
    # The trajectories timed are the seed's: what they did is the same, only the time differs.
    assert py.crossings_per_collision == cl["crossings_per_collision"]
    assert len(py.samples) == 3 and py.threads == 1 and py.ns_per_collision > 0
    assert isinstance(py, lg.BenchResult) and "collisions/s per thread" in repr(py)
    with pytest.raises(ValueError, match="observe 'all' is not one of"):
        lg.bench(observe="all")
    with pytest.raises(ValueError, match="straight_beside"):
        lg.bench(straight_beside=True)
    with pytest.raises(ValueError, match="oracle_floor=true: .* nonzero field"):
        lg.bench(oracle_floor=True)


def test_the_arc_engines_winner_only_floor_runs_on_a_tape_of_its_own_events(cli_json):
    args = dict(w="0.1", field="1", collisions_per_thread=3.2e4, repetitions=3)
    py = lg.bench(oracle_floor=True, **args)
    if py.meta["engine"] != "simd":
        pytest.skip("no SIMD arc engine on this CPU")
    o = py.oracle
    # A tape of collisions/16 steps, an event of every one of the 16 lanes per step.
    assert o["steps"] == 2000 and o["events"] == 16 * 2000
    assert 0.5 * o["events"] < o["collisions"] < o["events"]
    assert o["floor_collisions_per_second"] == pytest.approx(1e9 / o["floor_ns_per_collision"])
    # The tape is the seed's: the command line records the same events.
    cl = cli_json("bench", "--w", "0.1", "--field", "1", "--collisions-per-thread", "3.2e4",
                  "--repetitions", "3", "--oracle-floor")
    assert cl["oracle"]["collisions"] == o["collisions"]
    with pytest.raises(ValueError, match="oracle_floor"):
        lg.bench(oracle_floor=True, engine="scalar", **args)


def test_free_paths_have_the_command_lines_bits(cli_json):
    py = lg.free_paths(scene="square", radius="1/1000", collisions=6.4e4, batches=4, seed=3)
    cl = cli_json("free-paths", "--scene", "square", "--radius", "1/1000", "--collisions", "6.4e4",
                  "--batches", "4", "--seed", "3")
    same(py.to_dict(), cl)
    assert list(py.bins["probability"]) == [b["probability"] for b in cl["bins"]]
    assert np.isnan(py.bins["hi"][-1]) and cl["bins"][-1]["hi"] is None
    assert py.flights == "jump" and "long flights jumped" in str(py)


def test_str_of_lyapunov_and_free_paths_is_the_command_lines_text(cli):
    for py, args in [
        (lambda: lg.lyapunov(w="0.1", collisions_per_batch=2e4, batches=4, starts=2, seed=3),
         ["lyapunov", "--w", "0.1", "--collisions-per-batch", "2e4", "--batches", "4",
          "--starts", "2", "--seed", "3"]),
        (lambda: lg.free_paths(scene="square", radius="1/100", collisions=3.2e4, batches=4),
         ["free-paths", "--scene", "square", "--radius", "1/100", "--collisions", "3.2e4",
          "--batches", "4"]),
    ]:
        code, out, err = cli(*args, "--quiet")
        assert code == 0, err
        assert str(py()) == out.rstrip("\n")


def test_str_of_a_sweep_is_the_command_lines_table(cli, tmp_path):
    py = lg.sweep(w_from="0.1", w_to="0.2", steps=2, runs=2, collisions_per_run=1e6,
                  batches_per_run=2, seed=5)
    code, out, err = cli("sweep", "--w-from", "0.1", "--w-to", "0.2", "--steps", "2", "--runs", "2",
                         "--collisions-per-run", "1e6", "--batches-per-run", "2", "--seed", "5",
                         "--out", str(tmp_path / "sweep"), "--quiet")
    assert code == 0, err
    # The command line then lists the files it wrote; the rest is the same text.
    table = out.rstrip("\n").rsplit("\n", 1)[0]
    assert out.rstrip("\n").rsplit("\n", 1)[1].startswith("written: ")
    assert str(py) == table

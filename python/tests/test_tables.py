"""Any periodic table given as data (``table=``): a TOML file or a dict, the same bits as the
command line's ``--table``, its refusals as ``ValueError`` naming the disks or the corridor."""

import copy
from fractions import Fraction

import numpy as np
import pytest

import lorentz_gas as lg
from conftest import REPO

TABLE = REPO / "examples" / "tables" / "two-radius-square.toml"

TWO_RADII = {
    "name": "two-radius square",
    "lattice": {"e1": [1, 0], "e2": ["0", "1"]},
    "disks": [
        {"centre": [0, 0], "radius": Fraction(2, 5)},
        {"centre": ["1/2", "0.5"], "radius": "1/5"},
    ],
}


def _physics(d):
    return {k: d[k] for k in ("D", "D_err", "D_check", "batch_D", "identities")}


def test_a_table_file_and_a_dict_give_the_command_lines_bits(cli_json):
    args = dict(collisions=2e6, batches=4, seed=5)
    from_file = lg.diffusion(table=TABLE, **args)
    assert isinstance(from_file, lg.TableDiffusionResult)
    from_dict = lg.diffusion(table=TWO_RADII, **args)
    cli = cli_json("diffusion", "--table", str(TABLE), "--collisions", "2e6", "--batches", "4",
                   "--seed", "5")
    assert _physics(from_file.to_dict()) == _physics(cli)
    # The dict writes one centre as 0.5 instead of 1/2: the same exact table, the same bits.
    assert _physics(from_dict.to_dict())["batch_D"] == cli["batch_D"]
    mfp = next(i for i in from_file.identities if i["name"] == "mean free path")
    assert mfp["agrees"], mfp
    assert "two-radius square" in str(from_file) and "mean free path" in str(from_file)


def test_open_corridors_and_overlaps_are_value_errors_naming_them():
    open_table = copy.deepcopy(TWO_RADII)
    open_table["disks"][1]["radius"] = "1/20"
    with pytest.raises(ValueError, match=r"infinite horizon: the corridor along 1 e1 \+ 0 e2"):
        lg.diffusion(table=open_table, collisions=1e6, batches=4)
    overlap = copy.deepcopy(TWO_RADII)
    overlap["disks"][1]["radius"] = "0.31"
    for call in (lg.diffusion, lg.lyapunov, lg.audit):
        with pytest.raises(ValueError, match=r"disk 1 \(centre \(0, 0\), radius 2/5\) and disk 2"):
            call(table=overlap)
    # What a table lacks is named: true shadowing needs one disk per cell at the lattice points.
    with pytest.raises(ValueError, match=r"lacks one disk per cell, at the lattice points, which the shadow analysis"):
        lg.shadow(table=TABLE, segments=1, collisions_per_segment=20)
    with pytest.raises(ValueError, match=r"rel_err=0\.001 is out of range"):
        lg.diffusion(table=TABLE, rel_err=1e-3)
    with pytest.raises(ValueError, match="table= gives the whole table"):
        lg.diffusion(w="0.1", table=TABLE)
    with pytest.raises(ValueError, match="not a table"):
        lg.diffusion(table={"lattice": {"e1": [1, 0], "e2": [0, 1]}, "disk": []})
    with pytest.raises(OSError, match="no-such-table.toml"):
        lg.diffusion(table="no-such-table.toml")


def test_the_orbit_analyses_take_a_table():
    ly = lg.lyapunov(table=TABLE, collisions_per_batch=2e4, batches=4, starts=2)
    assert ly.tangent["per_collision"] > 0
    au = lg.audit(table=TABLE, collisions=2e4, batches=2)
    assert au.summary["outside"] == 0 and au.summary["audited"] > 0
    ev = lg.events(table=TABLE, n=500, seed=2)
    assert len(ev) == 501 and np.all(np.diff(ev["t"]) >= 0)
    # The same orbit in chunks.
    tr = lg.Trajectory(table=TWO_RADII, seed=2)
    chunks = np.concatenate([tr.start, tr.events(200), tr.events(300)])
    assert (chunks == ev).all()


def test_a_table_in_a_field_runs_on_the_simd_engine_and_its_results_pass_the_audit(tmp_path, cli_json):
    args = dict(collisions=2e6, batches=8, seed=3)
    straight = lg.diffusion(table=TABLE, **args)
    cli = cli_json("diffusion", "--table", str(TABLE), "--collisions", "2e6", "--batches", "8",
                   "--seed", "3", "--engine", "scalar")
    # Both engines, Python and the command line: the same bits.
    assert _physics(straight.to_dict()) == _physics(cli)
    field = lg.diffusion(table=TWO_RADII, field=3, **args)
    assert abs(field.localized_fraction_exact - 0.0775) < 1e-3
    assert abs(field.mean_free_time - field.mean_free_time_exact) < 6 * field.mean_free_time_err
    ev = lg.events(table=TABLE, field=1, n=300, seed=2)
    assert len(ev) == 301 and np.all(np.diff(ev["t"]) >= 0)
    for r in (straight, field):
        path = tmp_path / f"{id(r)}.json"
        path.write_text(r.to_json())
        report = lg.report(path, out=tmp_path / f"{id(r)}-report")
        assert report.verdict == "PASS", str(report)


def test_a_sweep_over_the_field_of_a_table_has_the_command_lines_bits(tmp_path, cli_json):
    r = lg.sweep(table=TABLE, fields=[-3, 3], collisions_per_run=2e5, batches_per_run=8,
                 localization_samples=1e5)
    cli = cli_json("sweep", "--table", str(TABLE), "--fields=-3,3", "--collisions-per-run", "2e5",
                   "--batches-per-run", "8", "--localization-samples", "1e5", "--out",
                   str(tmp_path / "cli"))
    assert list(r.to_dict()["rows"]) == list(cli["rows"])
    assert r.onsager_agrees and "w" not in r.to_dict()["rows"][0]
    with pytest.raises(ValueError, match="table= gives the whole table"):
        lg.sweep(table=TABLE, w="0.1", fields=[1])
    with pytest.raises(ValueError, match="scene, radius and table are for a sweep over the field"):
        lg.sweep(table=TABLE, w_from="0.1", w_to="0.2", steps=2)


def test_bench_times_a_table_beside_the_triangular_gas_as_the_command_line_does(cli_json):
    args = dict(w="0.1", collisions_per_thread=4e4, repetitions=3, progress=False)
    r = lg.bench(table=TABLE, **args)
    t = r.table
    assert t["table"].startswith("two-radius square (e1 = (1, 0)")
    assert len(t["samples"]) == 3 and min(t["samples"]) > 0
    assert t["collisions_per_second_per_thread"] > 0 and t["over_triangular"] > 0
    assert t["paired_ratio"] > 0 and t["crossings_per_collision"] > 0
    # The triangular gas's own throughput beside it, in the same run.
    assert len(r.samples) == 3 and r.collisions_per_second_per_thread > 0
    assert abs(t["over_triangular"] - np.median(t["samples"]) / np.median(r.samples)) < 1e-9
    cli = cli_json("bench", "--w", "0.1", "--table", str(TABLE), "--collisions-per-thread", "4e4",
                   "--repetitions", "3")
    assert set(cli["table"]) == set(t) and cli["table"]["table"] == t["table"]
    # Timings differ between runs; the trajectories do not: the same crossings, from a dict too.
    assert cli["table"]["crossings_per_collision"] == t["crossings_per_collision"]
    from_dict = lg.bench(table=TWO_RADII, **args).table
    assert from_dict["crossings_per_collision"] == t["crossings_per_collision"]
    assert "table" not in lg.bench(**args).keys()


def test_bench_refuses_a_bad_table_naming_the_problem():
    overlap = copy.deepcopy(TWO_RADII)
    overlap["disks"][1]["radius"] = "0.31"
    with pytest.raises(ValueError, match=r"disk 1 \(centre \(0, 0\), radius 2/5\) and disk 2"):
        lg.bench(table=overlap, collisions_per_thread=1e4, repetitions=1)
    with pytest.raises(ValueError, match="not a table"):
        lg.bench(table={"lattice": {"e1": [1, 0], "e2": [0, 1]}, "disk": []})
    with pytest.raises(ValueError, match="field=1: a table is timed by its bare straight flights"):
        lg.bench(table=TABLE, field=1, collisions_per_thread=1e4, repetitions=1)
    with pytest.raises(ValueError, match="use f64 with a table"):
        lg.bench(table=TABLE, precision=128, collisions_per_thread=1e4, repetitions=1)
    with pytest.raises(ValueError, match="table: long_flights= times one lattice"):
        lg.bench(table=TABLE, long_flights=["1/4"])
    with pytest.raises(OSError, match="no-such-table.toml"):
        lg.bench(table="no-such-table.toml")

"""Result files both ways: every kind of result the command line writes (``--json``, or into its
output folders) is read back by ``lg.load`` as its result object, with each of its tables in
``to_pandas(table)``; ``save`` writes the same bytes again; and the command line reads what
Python saved (``lorentz report`` audits it, ``lorentz merge`` merges the parts)."""

import json
import os
import pathlib

import pytest

import lorentz_gas as lg
from conftest import REPO

TABLE = str(REPO / "examples" / "tables" / "two-radius-square.toml")

# Each kind the command line prints with --json: (its class, the command at small statistics).
PRINTED = {
    "diffusion": (lg.DiffusionResult, ["diffusion", "--w", "0.2", "--collisions", "8e5",
                                       "--batches", "8"]),
    "table-diffusion": (lg.TableDiffusionResult, ["diffusion", "--table", TABLE, "--collisions",
                                                  "4e5", "--batches", "8"]),
    "field": (lg.FieldResult, ["diffusion", "--w", "0.1", "--collisions", "4e5", "--batches", "8",
                               "--field", "1/2", "--localization-samples", "1e4"]),
    "hops": (lg.HopsResult, ["hops", "--w", "0.1", "--collisions", "1e6", "--batches", "4",
                             "--order", "2"]),
    "theory": (lg.TheoryResult, ["theory", "--w", "0.1", "--collisions", "1e6", "--batches", "4",
                                 "--order", "2"]),
    "lattice-walk": (lg.LatticeWalkResult, ["lattice-walk", "--w", "0.1", "--collisions", "1e6",
                                            "--batches", "4", "--order", "2"]),
    "backscatter": (lg.BackscatterResult, ["backscatter", "--w", "0.1", "--particles", "2e4",
                                           "--batches", "4"]),
    "escape": (lg.EscapeResult, ["escape", "--w", "0.1", "--particles-per-width", "3200"]),
    "lyapunov": (lg.LyapunovResult, ["lyapunov", "--w", "0.1", "--collisions-per-batch", "1000",
                                     "--batches", "2"]),
    "lyapunov-field": (lg.LyapunovResult, ["lyapunov", "--w", "0.1", "--field", "1/2",
                                           "--collisions-per-batch", "1000", "--batches", "2"]),
    "superdiffusion": (lg.SuperdiffusionResult, ["superdiffusion", "--scene", "square", "--radius",
                                                 "1/4", "--collisions", "3.2e5", "--batches", "16",
                                                 "--octaves", "4"]),
    "free-paths": (lg.FreePathResult, ["free-paths", "--scene", "square", "--radius", "0.1",
                                       "--collisions", "1e5"]),
    "audit": (lg.AuditResult, ["audit", "--w", "0.1", "--collisions", "2e4", "--batches", "2"]),
    "shadow": (lg.ShadowResult, ["shadow", "--w", "0.1", "--collisions-per-segment", "100",
                                 "--segments", "2"]),
    "certify": (lg.CertifyResult, ["certify", "--w", "0.1", "--collisions", "50"]),
    "trajectory": (lg.TrajectoryResult, ["trajectory", "--scene", "square", "--radius", "1/4",
                                         "--start", "1/2,1/10", "--direction", "1,1/3", "--time",
                                         "1/3", "--digits", "20"]),
    "section": (lg.SectionResult, ["section", "--w", "0.1", "--collisions", "100"]),
    "constants": (lg.ConstantsResult, ["constants", "--w", "0.1"]),
    "bench": (lg.BenchResult, ["bench", "--w", "0.1", "--collisions-per-thread", "1e5",
                               "--repetitions", "2"]),
    "bench-long-flights": (lg.BenchResult, ["bench", "--long-flights", "1/4,1/8",
                                            "--collisions-per-radius", "1e4", "--repetitions", "2"]),
    "observer-costs": (lg.ObserverCostsResult, ["bench", "--w", "0.1", "--observer-costs",
                                                "--collisions-per-thread", "1e5",
                                                "--repetitions", "1"]),
}

# The kinds `lorentz report` audits: a file Python saved must pass its quick audit.
AUDITED = {"diffusion", "table-diffusion", "field", "hops", "theory", "lattice-walk",
           "backscatter", "escape", "sweep", "field-sweep"}


def _printed(cli, kind, tmp_path):
    """The kind's --json output, written to a file: (the file, its text)."""
    args = PRINTED[kind][1]
    quiet = [] if kind == "constants" else ["--quiet"]
    code, out, err = cli(*args, "--json", *quiet)
    assert code == 0, err
    path = tmp_path / f"{kind}.json"
    path.write_text(out)
    return path, out


def _round_trip(path, cls, tmp_path, cli=None, kind=""):
    """Loads ``path`` (a file the command line wrote), checks its class, text and tables, saves it
    and loads the copy; returns the result and the copy's path."""
    r = lg.load(path)
    assert type(r) is cls, (path, type(r))
    text = pathlib.Path(path).read_text()
    assert r.to_json() + "\n" == text or r.to_json() == text
    copy = tmp_path / f"saved-{pathlib.Path(path).name}"
    assert r.save(copy) == str(copy)
    assert copy.read_text().rstrip("\n") == text.rstrip("\n"), "save wrote other text"
    again = lg.load(copy)
    assert type(again) is cls and again.to_dict() == r.to_dict()
    _tables_read(r)
    return r, copy


def _tables_read(r):
    """Every table of ``r`` as a DataFrame: one row per record of the structured array."""
    pd = pytest.importorskip("pandas")
    tables = r._all_tables()
    assert sorted(tables) == r.table_names()
    for name, table in tables.items():
        df = r.to_pandas(name)
        assert isinstance(df, pd.DataFrame) and len(df) == len(table), name
        assert list(df.columns) == list(table.dtype.names), name
    with pytest.raises(ValueError, match="tables are"):
        r.to_pandas("no-such-table")


def _audited(cli, path, tmp_path):
    """`lorentz report PATH --quick`: it reads the file and every check passes (the verdict on the
    first line)."""
    out = tmp_path / (pathlib.Path(path).stem + "-audit")
    code, text, err = cli("report", str(path), "--quick", "--out", str(out), "--quiet")
    first = text.splitlines()[0] if text else ""
    assert code == 0 and ": PASS" in first, f"{code} {first}\n{text}{err}"


@pytest.mark.parametrize("kind", sorted(PRINTED))
def test_each_printed_kind_loads_saves_and_is_read_back(kind, cli, tmp_path):
    path, _ = _printed(cli, kind, tmp_path)
    _, copy = _round_trip(path, PRINTED[kind][0], tmp_path)
    if kind in AUDITED:
        _audited(cli, copy, tmp_path)


def test_the_tables_hold_the_results_arrays(cli, tmp_path):
    pytest.importorskip("pandas")
    d = lg.load(_printed(cli, "diffusion", tmp_path)[0])
    batches = d.to_pandas("batches")
    assert list(batches["D"]) == list(d.batch_D) and list(batches["batch"]) == list(range(8))
    msd = d.to_pandas("msd")
    assert list(msd["times"]) == list(d.msd_times) and list(msd["msd"]) == list(d.msd)
    # Without a name: the result's scalars, as before.
    assert d.to_pandas()["D"][0] == d.D
    h = lg.load(_printed(cli, "hops", tmp_path)[0])
    pairs = h.to_pandas("pairs")
    assert len(pairs) == 9 and dict(zip(pairs["sequence"], pairs["value"])) == h.pairs
    assert list(h.to_pandas("correlations")["lag"])[:2] == [1, 2]
    t = lg.load(_printed(cli, "theory", tmp_path)[0])
    assert list(t.to_pandas("orders")["k"]) == [o["k"] for o in t.orders]
    ly = lg.load(_printed(cli, "lyapunov", tmp_path)[0])
    assert list(ly.to_pandas()["precision"]) == [r["precision"] for r in ly.to_dict()["divergence"]]


def test_sweep_folders_and_their_parts(cli, tmp_path):
    """sweep.json, field-sweep.json and a part's shard.json, read from the folder the command
    line wrote; the parts saved from Python are merged by `lorentz merge` into the whole sweep."""
    sweep = ["--w-from", "0.1", "--w-to", "0.2", "--steps", "2", "--runs", "2",
             "--collisions-per-run", "2e5", "--batches-per-run", "4"]
    code, _, err = cli("sweep", *sweep, "--out", str(tmp_path / "whole"), "--quiet")
    assert code == 0, err
    whole, copy = _round_trip(tmp_path / "whole" / "sweep.json", lg.SweepResult, tmp_path)
    assert type(lg.load(tmp_path / "whole")) is lg.SweepResult, "the folder names its one result"
    assert len(whole.to_pandas("runs")) == 4
    _audited(cli, copy, tmp_path)
    for i in (0, 1):
        part = tmp_path / f"part{i}"
        code, _, err = cli("sweep", *sweep, "--shard", f"{i}/2", "--out", str(part), "--quiet")
        assert code == 0, err
        shard = lg.load(part / "shard.json")
        assert type(shard) is lg.ShardResult and shard.shard["index"] == i
        (part / "shard.json").unlink()
        shard.save(part / "shard.json")
    code, _, err = cli("merge", str(tmp_path / "part0"), str(tmp_path / "part1"), "--out",
                       str(tmp_path / "merged"), "--quiet")
    assert code == 0, err
    merged = lg.load(tmp_path / "merged" / "sweep.json")
    assert merged.to_dict()["rows"] == whole.to_dict()["rows"]

    code, _, err = cli("sweep", "--scene", "square", "--radius", "1/4", "--fields", "1,-1",
                       "--collisions-per-run", "2e5", "--batches-per-run", "8",
                       "--out", str(tmp_path / "fs"), "--quiet")
    assert code == 0, err
    _, copy = _round_trip(tmp_path / "fs" / "field-sweep.json", lg.FieldSweepResult, tmp_path)
    _audited(cli, copy, tmp_path)


def test_documents_of_the_other_commands(cli, tmp_path):
    """report.json, a figure's files and its data, and a Slurm campaign's scripts."""
    path, _ = _printed(cli, "diffusion", tmp_path)
    code, out, err = cli("report", str(path), "--quick", "--out", str(tmp_path / "rep"),
                         "--json", "--quiet")
    assert code == 0, err
    report, _ = _round_trip(tmp_path / "rep" / "report.json", lg.ReportResult, tmp_path)
    assert report.to_dict() == json.loads(out) and report.verdict.startswith("PASS")
    assert len(report.to_pandas("checks")) == len(report.checks)
    code, out, err = cli("figure", "backscatter-map", "--particles", "2000", "--out",
                         str(tmp_path / "fig"), "--json", "--quiet")
    assert code == 0, err
    (tmp_path / "figure.json").write_text(out)
    figure, _ = _round_trip(tmp_path / "figure.json", lg.FigureResult, tmp_path)
    data = next(f for f in figure.files if f.endswith(".json"))
    _round_trip(tmp_path / "fig" / data, lg.FigureDataResult, tmp_path)
    code, out, err = cli("slurm", "sweep", "--w-from", "0.1", "--w-to", "0.2", "--steps", "2",
                         "--array", "2", "--out", str(tmp_path / "campaign"), "--json",
                         "--quiet")
    assert code == 0, err
    (tmp_path / "slurm.json").write_text(out)
    _round_trip(tmp_path / "slurm.json", lg.SlurmResult, tmp_path)


def test_a_result_saved_from_python_passes_the_command_lines_audit(cli, tmp_path):
    d = lg.diffusion(w="0.2", collisions=8e5, batches=8)
    d.save(tmp_path / "d.json")
    _audited(cli, tmp_path / "d.json", tmp_path)
    s = lg.sweep(w_from="0.1", w_to="0.2", steps=2, runs=2, collisions_per_run=2e5,
                 batches_per_run=4)
    s.save(tmp_path / "s.json")
    _audited(cli, tmp_path / "s.json", tmp_path)
    assert lg.load(tmp_path / "s.json").to_dict() == s.to_dict()


def test_save_never_overwrites_nor_follows_a_link(tmp_path):
    r = lg.diffusion(w="0.2", collisions=2e5, batches=4)
    path = tmp_path / "d.json"
    r.save(path)
    r.save(path)  # the same bytes: nothing to do
    other = lg.diffusion(w="0.2", collisions=2e5, batches=4, seed=2)
    with pytest.raises(ValueError, match="holds another result"):
        other.save(path)
    assert lg.load(path).to_json() == r.to_json(), "a file was overwritten"
    (tmp_path / "link.json").symlink_to(tmp_path / "elsewhere.json")
    with pytest.raises(ValueError, match="a link, never written through"):
        r.save(tmp_path / "link.json")
    assert not (tmp_path / "elsewhere.json").exists()
    assert [p.name for p in tmp_path.iterdir() if p.name.startswith(".")] == [], "a temporary left"


BAD = {
    "not JSON": ("{\"D\": 1,", "not a JSON result of lorentz"),
    "a key twice": ("{\"batch_D\": [1], \"batch_D\": [2], \"msd_times\": []}", "given twice"),
    "NaN": ("{\"D\": NaN}", "NaN is not JSON"),
    "not an object": ("[1, 2]", "not a JSON object"),
    "no kind": ("{\"colour\": \"blue\"}", r"none of the keys that identify the kinds known: "
                                          r"table-diffusion \(batch_D, identities, table\)"),
    "a malformed sweep": ("{\"rows\": \"many\", \"linear_fit\": {}}", "a malformed sweep result"),
    "a malformed lyapunov": ("{\"tangent\": {}, \"divergence\": 3}", "a malformed lyapunov"),
    "not UTF-8": (b"{\"D\": \"\xff\"}", "not UTF-8"),
    "deep": ("[" * 100000 + "]" * 100000, "not a JSON result"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_a_file_that_is_not_a_result_is_refused_naming_it(case, tmp_path):
    content, message = BAD[case]
    path = tmp_path / "bad.json"
    (path.write_bytes if isinstance(content, bytes) else path.write_text)(content)
    with pytest.raises(ValueError, match=message) as e:
        lg.load(path)
    assert str(e.value).startswith(str(path)), "the message names the file"


def test_what_is_not_a_regular_file_is_refused(tmp_path):
    os.mkfifo(tmp_path / "pipe.json")
    with pytest.raises(ValueError, match="not a regular file"):
        lg.load(tmp_path / "pipe.json")  # refused, not waited on
    with pytest.raises(ValueError, match="a folder with none of the result files"):
        lg.load(tmp_path)
    with pytest.raises(OSError, match="missing.json"):
        lg.load(tmp_path / "missing.json")
    big = tmp_path / "big.json"
    with open(big, "wb") as f:
        f.truncate(65 << 20)
    with pytest.raises(ValueError, match="more than a result file's"):
        lg.load(big)

"""Result objects: arrays, a readable repr, to_dict and to_json, pandas."""

import json
import pathlib
import re
import shutil

import numpy as np
import pytest

import lorentz_gas as lg


@pytest.fixture(scope="module")
def run():
    return lg.diffusion(w=0.1, collisions=4e6, batches=8)


def test_repr_says_d_with_its_error(run):
    assert re.fullmatch(r"<DiffusionResult: D = 0\.\d{6} ± 0\.\d{6} at w = 0\.1>", repr(run))


def test_arrays_and_their_shapes(run):
    assert run.msd_times.dtype == np.float64 and run.msd.shape == run.msd_times.shape
    assert run.batch_D.shape == (8,)
    assert np.allclose(run.msd, 4 * run.msd_times * run.msd_over_4t)
    assert isinstance(run.meta, dict) and run.meta["seed"] == 1
    assert run.batch_msd.shape == (8, len(run.msd_times))


def test_to_dict_and_to_json_agree(run):
    d = run.to_dict()
    assert d == json.loads(run.to_json())
    assert d["D"] == run.D and isinstance(d["batch_D"], list)


def test_the_error_is_the_standard_error_of_the_batches(run):
    se = run.batch_D.std(ddof=1) / np.sqrt(len(run.batch_D))
    assert run.D_err == pytest.approx(se, rel=1e-12)


def test_sweep_rows_as_arrays_and_pandas():
    s = lg.sweep(w_from="0.1", w_to="0.2", steps=2, runs=2, collisions_per_run=1e6, batches_per_run=2)
    assert list(s.w) == [0.1, 0.2]
    assert s.D.shape == (2,) and "2 points" in repr(s)
    assert s.rows.shape == (2,) and list(s.rows["D"]) == list(s.D)
    assert s.run_D.shape == (2, 2)
    assert s.rows[0]["w"] == 0.1
    pd = pytest.importorskip("pandas")
    df = s.to_pandas()
    assert isinstance(df, pd.DataFrame) and list(df["w"]) == [0.1, 0.2]


def _untimed(text):
    """The text without what differs between two runs of the same bits: the wall time and speed
    of the header and the time of the precision plan."""
    text = re.sub(r"\d+ threads?, [\d.]+ s, [\d.e+]+ collisions/s", "TIME", text)
    return re.sub(r"about .* here", "about TIME here", text)


def _unclocked(text):
    """``_untimed`` and also every other wall time (``2.4 s)``, ``in 1.8 s``) and the thread
    count beside it."""
    text = re.sub(r"\d+ threads?, ", "THREADS, ", _untimed(text))
    return re.sub(r"\b\d+\.\d s\b", "T s", text)


# Each kind the library renders: (the Python call, the same run on the command line).
_TEXT_KINDS = {
    "field": (
        lambda: lg.diffusion(w=0.1, collisions=4e5, batches=4, field="1/2", localization_samples=1e4),
        ["diffusion", "--w", "0.1", "--collisions", "4e5", "--batches", "4", "--field", "1/2",
         "--localization-samples", "1e4"],
    ),
    "field-localized": (
        lambda: lg.diffusion(w=0.1, collisions=4e5, batches=4, field=100, localization_samples=1e4),
        ["diffusion", "--w", "0.1", "--collisions", "4e5", "--batches", "4", "--field", "100",
         "--localization-samples", "1e4"],
    ),
    "hops": (
        lambda: lg.hops(w=0.1, collisions=1e6, batches=4, order=2),
        ["hops", "--w", "0.1", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    ),
    "theory": (
        lambda: lg.theory(w=0.1, collisions=1e6, batches=4, order=2),
        ["theory", "--w", "0.1", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    ),
    "lattice-walk": (
        lambda: lg.lattice_walk(w=0.1, collisions=1e6, batches=4, order=2),
        ["lattice-walk", "--w", "0.1", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    ),
    "backscatter": (
        lambda: lg.backscatter(w=0.1, particles=1e5, batches=4),
        ["backscatter", "--w", "0.1", "--particles", "1e5", "--batches", "4"],
    ),
    "escape": (
        lambda: lg.escape(w=0.1, particles_per_width=3200),
        ["escape", "--w", "0.1", "--particles-per-width", "3200"],
    ),
    "certify": (
        lambda: lg.certify(w=0.1, collisions=50),
        ["certify", "--w", "0.1", "--collisions", "50"],
    ),
    "cycles": (
        lambda: lg.cycles(max_length=4),
        ["cycles", "--max-length", "4"],
    ),
    "shadow": (
        lambda: lg.shadow(w=0.1, collisions_per_segment=100, segments=4),
        ["shadow", "--w", "0.1", "--collisions-per-segment", "100", "--segments", "4"],
    ),
    "superdiffusion": (
        lambda: lg.superdiffusion(radius="1/4", scene="square", collisions=3.2e6, batches=16, octaves=6),
        ["superdiffusion", "--scene", "square", "--radius", "1/4", "--collisions", "3.2e6",
         "--batches", "16", "--octaves", "6"],
    ),
    "audit": (
        lambda: lg.audit(w=0.1, collisions=2e4, batches=2, field="1/2"),
        ["audit", "--w", "0.1", "--collisions", "2e4", "--batches", "2", "--field", "1/2"],
    ),
}


@pytest.mark.parametrize("kind", sorted(_TEXT_KINDS))
def test_str_of_each_kind_is_the_command_lines_text(kind, cli):
    call, args = _TEXT_KINDS[kind]
    result = call()
    assert result._text_kind == kind.split("-localized")[0]
    code, out, err = cli(*args, "--quiet")
    assert code == 0, err
    assert _unclocked(str(result)) == _unclocked(out.rstrip("\n"))
    assert not str(result).startswith(type(result).__name__), "the generic table, not the text"


# Kinds whose text the call that made them renders (it needs what the JSON does not hold: the
# time as typed, the formulas, the folder written into). Each: (the Python call given a folder,
# the command line given the same folder).
_PRINTED_KINDS = {
    "trajectory": (
        lambda out: lg.trajectory(("1/2", "1/10"), ("1", "1/3"), "1/3", radius="1/4", digits=20),
        lambda out: ["trajectory", "--scene", "square", "--radius", "1/4", "--start", "1/2,1/10",
                     "--direction", "1,1/3", "--time", "1/3", "--digits", "20"],
    ),
    "trajectory-field": (
        lambda out: lg.trajectory(("21/20", "3/5"), ("1", "0"), "5", w="1/10", field="1/2"),
        lambda out: ["trajectory", "--scene", "triangular", "--w", "1/10", "--start", "21/20,3/5",
                     "--direction", "1,0", "--time", "5", "--field", "1/2"],
    ),
    "constants-square": (
        lambda out: lg.constants(radius="1/4"),
        lambda out: ["constants", "--scene", "square", "--radius", "1/4"],
    ),
    "constants-triangular": (
        lambda out: lg.constants(w="1/10", precision=128),
        lambda out: ["constants", "--scene", "triangular", "--w", "1/10", "--precision", "128"],
    ),
    "figure": (
        lambda out: lg.figure("backscatter-map", particles=2000, out=out),
        lambda out: ["figure", "backscatter-map", "--particles", "2000", "--out", out],
    ),
}


@pytest.mark.parametrize("kind", sorted(_PRINTED_KINDS))
def test_str_of_a_kind_the_call_renders_is_the_command_lines_text(kind, cli, tmp_path):
    call, args = _PRINTED_KINDS[kind]
    result = call(str(tmp_path / "py"))
    # `constants` computes at once: it has no progress to quieten.
    quiet = [] if kind.startswith("constants") else ["--quiet"]
    code, out, err = cli(*args(str(tmp_path / "py")), *quiet)
    assert code == 0, err
    assert str(result) == out.rstrip("\n")
    assert not str(result).startswith(type(result).__name__), "the generic table, not the text"


def test_str_of_a_report_is_the_command_lines_text(cli, tmp_path):
    # A result made in Python: no command line is recorded, so both audits judge the same
    # checks (the command line's own report parses a recorded command line; Python cannot).
    d = lg.diffusion(w=0.1, collisions=1.6e6, batches=16)
    (tmp_path / "d.json").write_text(d.to_json())
    result = lg.report(tmp_path / "d.json", out=tmp_path / "r", quick=True)
    code, out, err = cli("report", str(tmp_path / "d.json"), "--quick", "--out",
                         str(tmp_path / "r"), "--quiet")
    assert code == 0, err
    # Each audit draws its re-run batch afresh (operating-system entropy), so the numbers of the
    # re-run checks differ between the two: the lines, checks and verdicts are the same.
    drawn = lambda text: re.sub(r"\d+(\.\d+)?(e[-+]?\d+)?", "N", _unclocked(text))
    assert drawn(str(result)) == drawn(out.rstrip("\n"))
    # The verdict first, where a reader (and `head -1`) sees it; the documents written last.
    first = str(result).splitlines()[0]
    assert "d.json: PASS (quick audit: 1 of 16 batches re-run" in first, first
    assert str(result).splitlines()[-1] == f"written: {tmp_path / 'r'}/report.{{md,html,json}}"


def test_a_result_goes_straight_into_the_audit(tmp_path):
    d = lg.diffusion(w=0.1, collisions=1.6e6, batches=16)
    audit = tmp_path / "audit"
    assert lg.report(d, out=audit, quick=True).verdict == "PASS"
    assert (audit / "result.json").read_text() == d.to_json() + "\n"
    assert (audit / "report.json").is_file()
    # Again into the same folder: the same file is found there and audited again.
    assert lg.report(d, out=audit, quick=True).verdict == "PASS"
    other = lg.diffusion(w=0.1, collisions=1.6e6, batches=16, seed=2)
    with pytest.raises(ValueError, match="holds another result"):
        lg.report(other, out=audit, quick=True)
    assert (audit / "result.json").read_text() == d.to_json() + "\n", "a file was overwritten"
    # Without a folder: a new one in the temporary directory, named by the report.
    alone = lg.report(d, quick=True)
    assert alone.verdict == "PASS"
    written = str(alone).splitlines()[-1]
    folder = pathlib.Path(re.fullmatch(r"written: (.*)/report\.\{md,html,json\}", written)[1])
    assert folder.name.startswith("lorentz-report-") and folder != audit
    assert (folder / "result.json").read_text() == d.to_json() + "\n"
    shutil.rmtree(folder)
    # A link where the file would go is never written through.
    (tmp_path / "linked").mkdir()
    (tmp_path / "linked" / "result.json").symlink_to(tmp_path / "elsewhere.json")
    with pytest.raises(ValueError, match="not a regular file"):
        lg.report(d, out=tmp_path / "linked", quick=True)
    assert not (tmp_path / "elsewhere.json").exists()


def test_str_of_a_reproduction_is_the_command_lines_text_and_its_steps_resume_there(cli, tmp_path):
    # One reproduction (about 100 s on 2 cores), made in Python; the command line then finds
    # every step finished in the same folder and prints the same lines, each marked resumed
    # (a resumed step keeps the seconds it took).
    out = tmp_path / "rq"
    result = lg.reproduce("quick", out=out, progress=False)
    assert not any(s["resumed"] for s in result.steps)
    code, printed, err = cli("reproduce", "--budget", "quick", "--out", str(out), "--quiet")
    assert code == 0, err
    lines = printed.rstrip("\n").splitlines()
    assert len(lines) == len(result.steps) + 1
    assert all(" s (resumed)  " in line for line in lines[:-1])
    assert str(result) == printed.rstrip("\n").replace(" s (resumed)  ", " s  ")
    assert str(result).splitlines()[-1] == f"written: {out}/index.html"


def test_str_of_a_sweep_in_a_field_is_the_command_lines_text_before_its_files(cli, tmp_path):
    result = lg.sweep(scene="square", radius="1/4", fields=["1", "-1"], collisions_per_run=2e5,
                      batches_per_run=4)
    code, out, err = cli("sweep", "--scene", "square", "--radius", "1/4", "--fields", "1,-1",
                         "--collisions-per-run", "2e5", "--batches-per-run", "4",
                         "--out", str(tmp_path / "s"), "--quiet")
    assert code == 0, err
    *table, written = out.rstrip("\n").splitlines()
    assert written.startswith(f"written: {tmp_path / 's'}/field-sweep.")
    assert str(result) == "\n".join(table)
    assert str(result).splitlines()[-1].startswith("Onsager-Casimir at radius = 0.25, |B| = 1:")
    pytest.importorskip("pandas")
    assert list(result.to_pandas()["field"]) == [1.0, -1.0]
    checks = result.to_pandas("onsager")
    c = result.onsager[0]
    assert list(checks["field"]) == [1.0] and list(checks["radius"]) == [0.25]
    assert checks["d_xx_even_z"][0] == c["d_xx_even"]["z"]
    assert checks["d_xy_odd_bound"][0] == c["d_xy_odd"]["bound"]


def test_str_is_the_command_lines_text(run, cli):
    code, out, err = cli("diffusion", "--w", "0.1", "--collisions", "4e6", "--batches", "8", "--quiet")
    assert code == 0, err
    assert _untimed(str(run)) == _untimed(out.rstrip("\n"))
    assert str(run).splitlines()[1].startswith("D              = ")


def test_str_and_html_show_every_scalar_with_its_error_to_its_place():
    # A result whose command-line text the library does not render: the generic table (here a
    # hops result with its text turned off).
    class PlainHops(lg.HopsResult):
        _text_kind = None

    run = PlainHops(lg.hops(w=0.1, collisions=1e6, batches=4, order=2).to_json())
    text = str(run)
    first, *rest = text.splitlines()
    assert first.startswith("PlainHops: ")
    d_line = next(l for l in rest if l.split()[0] == "D_GK")
    value, err = (float(x) for x in d_line.split()[1::2])
    # The error to two significant digits, the value to the same place.
    assert err == pytest.approx(run.D_GK_err, rel=0.05) and value == pytest.approx(run.D_GK, abs=err / 10)
    digits = len(d_line.split()[1].split(".")[1])
    assert digits == len(d_line.split()[3].split(".")[1])
    assert not any(l.split()[0] == "D_GK_err" for l in rest), "an error shown apart from its value"
    assert "seed 1, batches 4" in rest[-1]
    html = run._repr_html_()
    assert html.count("<tr>") == len(rest) - 1 and "<th style='text-align:left'>D_GK</th>" in html


def test_to_pandas_on_every_result_with_a_table_or_its_scalars(run):
    pd = pytest.importorskip("pandas")
    one = run.to_pandas()
    assert one.shape[0] == 1 and one["D"][0] == run.D and one["D_err"][0] == run.D_err
    sd = lg.superdiffusion(radius="1/4", scene="square", collisions=3.2e6, batches=16, octaves=6)
    with pytest.raises(ValueError, match="lags, limit_law"):
        sd.to_pandas()
    lags = sd.to_pandas(table="lags")
    assert list(lags["t"]) == list(sd.lags["t"])
    with pytest.raises(ValueError, match="tables are"):
        run.to_pandas(table="lags")


def test_help_explains_the_parameters():
    doc = lg.diffusion.__doc__
    for p in ["w :", "collisions :", "batches :", "seed :", "threads :", "engine :", "precision :"]:
        assert p in doc
    assert "0.3094" in doc


def test_a_python_result_file_passes_the_publication_audit(tmp_path):
    """`to_json()` is a result file the command line's `report` audits: re-run from its
    recorded configuration to the bit, identities, shadows — PASS; an edited D fails."""
    r = lg.diffusion(w="0.2", collisions=4e6, batches=8)
    good = tmp_path / "d.json"
    good.write_text(r.to_json())
    rep = lg.report(good, quick=True)
    assert rep.verdict == "PASS", [c for c in rep.checks if c["verdict"] != "PASS"]
    assert (tmp_path / "d-report" / "report.md").is_file()
    edited = r.to_dict()
    edited["D"] *= 1.001
    bad = tmp_path / "edited.json"
    bad.write_text(json.dumps(edited))
    assert lg.report(bad, quick=True).verdict == "FAIL"


def test_constants_are_typed_and_vectorised_over_gaps():
    one = lg.constants("0.1")
    assert isinstance(one, lg.ConstantsResult) and "w = 0.1" in repr(one)
    ws = ["0.05", "1/10", 0.2, "0.3"]
    table = lg.constants(ws)
    assert isinstance(table, lg.ConstantsTable) and len(table) == 4
    # Each entry is the single call's result, digit for digit.
    for w, r in zip(ws, table.results):
        assert r.to_json() == lg.constants(w).to_json()
    assert table.D_MZ.shape == (4,) and table.D_MZ[1] == one.D_MZ
    assert np.all(np.diff(table.mean_free_path) > 0)
    sq = lg.constants(radius=np.array([0.1, 0.25]))
    assert list(sq.radius) == [0.1, 0.25] and "D_MZ" not in sq.rows.dtype.names
    pd = pytest.importorskip("pandas")
    assert list(table.to_pandas()["w"]) == [0.05, 0.1, 0.2, 0.3]
    with pytest.raises(ValueError, match="not both"):
        lg.constants(w=[0.1], radius=[0.2])

"""Bad input raises ValueError with the command line's one-line message; I/O names the path."""

import fractions
import inspect

import pytest

import lorentz_gas as lg


def cli_message(cli, *args):
    code, _, err = cli(*args)
    assert code == 2, err
    line = err.strip().splitlines()[0]
    assert line.startswith("error: ")
    return line


@pytest.mark.parametrize(
    "kwargs, args",
    [
        (dict(w=0.5), ["--w", "0.5"]),
        (dict(w=0), ["--w", "0"]),
        (dict(w="nan"), ["--w", "nan"]),
        (dict(w=0.1, batches=1), ["--w", "0.1", "--batches", "1"]),
        (dict(w=0.1, precision=52), ["--w", "0.1", "--precision", "52"]),
        (dict(w=0.1, window=(40, 10)), ["--w", "0.1", "--window", "40:10"]),
        (dict(w=0.1, window=(10, 40), check_window=(10, 40)), ["--w", "0.1", "--check-window", "10:40"]),
        (dict(w=0.1, audit=2.0), ["--w", "0.1", "--audit", "2"]),
    ],
)
def test_library_refusals_are_the_command_lines_line(cli, kwargs, args):
    with pytest.raises(ValueError) as e:
        lg.diffusion(collisions=1000, **kwargs)
    line = cli_message(cli, "diffusion", "--collisions", "1000", *args)
    msg = str(e.value)
    assert "\n" not in msg
    # The library's words, not the command line's: no flag in a Python error.
    assert "--" not in msg, msg
    assert line.endswith(msg.split(": ", 1)[-1]) or line == "error: " + msg, (line, msg)


@pytest.mark.parametrize(
    "kwargs, flag, value",
    [
        (dict(collisions=2.5), "--collisions", "2.5"),
        (dict(collisions=-5), "--collisions", "-5"),
        (dict(collisions="2e99"), "--collisions", "2e99"),
        (dict(batches="many"), "--batches", "many"),
        (dict(w="1/0"), "--w", "1/0"),
        (dict(w="0.1.2"), "--w", "0.1.2"),
    ],
)
def test_value_parsing_refusals_are_the_command_lines(cli, kwargs, flag, value):
    args = {"w": 0.1, "collisions": 1000, **kwargs}
    with pytest.raises(ValueError) as e:
        lg.diffusion(**args)
    flags = {"--w": "0.1", "--collisions": "1000", flag: value}
    line = cli_message(cli, "diffusion", *[x for kv in flags.items() for x in kv])
    # Python names the parameter ("collisions: ..."), clap the flag; the message after is one.
    detail = str(e.value).split(": ", 1)[1]
    assert line.endswith(detail), (line, str(e.value))


def test_threads_engine_and_scene_are_checked():
    with pytest.raises(ValueError, match="threads must be from 1 to"):
        lg.diffusion(w=0.1, collisions=2e6, threads=0)
    with pytest.raises(ValueError, match="'auto', 'scalar', 'simd'"):
        lg.diffusion(w=0.1, collisions=2e6, engine="gpu")
    with pytest.raises(ValueError, match="0 < radius < 1/2"):
        lg.audit(scene="square", collisions=1000)
    with pytest.raises(ValueError, match="does not apply"):
        lg.audit(w=0.1, scene="square", radius=0.25, collisions=1000)
    with pytest.raises(TypeError):
        lg.diffusion(w=True, collisions=1000)


def test_exact_inputs_of_every_kind_give_one_gap():
    ws = [lg.constants(v).to_dict()["w_exact"] for v in ["0.1", "1/10", fractions.Fraction(1, 10), 0.1]]
    assert ws == ["1/10"] * 4


def test_a_misspelt_keyword_is_refused_naming_the_close_match():
    with pytest.raises(TypeError, match="'colisions'.*did you mean 'collisions'"):
        lg.diffusion(w=0.1, colisions=1e6)
    with pytest.raises(TypeError, match="did you mean 'checkpoint'"):
        lg.hops(w=0.1, checkpiont="x")
    with pytest.raises(TypeError, match="it takes"):
        lg.constants(w=0.1, zzzzzz=1)
    # The signatures (and so help() and the stubs test) are the functions' own.
    assert "collisions" in inspect.signature(lg.diffusion).parameters


def test_lossy_floats_are_refused_not_rounded():
    np = pytest.importorskip("numpy")
    # numpy.float32(0.1) is 0.100000001490116...: the run would be at another gap.
    with pytest.raises(ValueError, match="32-bit float"):
        lg.constants(np.float32(0.1))
    assert lg.constants(np.float64(0.1)).to_dict()["w_exact"] == "1/10"


def test_a_gap_beyond_w_inf_whose_double_lies_below_is_refused():
    # The nearest double of 0.30940107675850306 lies below w_inf, the decimal above it.
    for f in (lg.hops, lg.diffusion, lg.escape, lg.backscatter):
        with pytest.raises(ValueError, match="exactly as typed"):
            f(w="0.30940107675850306")


def test_a_fifo_as_checkpoint_is_refused_at_once(tmp_path):
    import os

    fifo = tmp_path / "fifo"
    os.mkfifo(fifo)
    with pytest.raises(ValueError, match="a FIFO"):
        lg.diffusion(w=0.1, collisions=1e6, batches=2, checkpoint=fifo)


def test_io_errors_raise_oserror_naming_the_path(tmp_path):
    bad = tmp_path / "file"
    bad.write_text("")
    target = bad / "checkpoint.ckpt"
    with pytest.raises(OSError) as e:
        lg.diffusion(w=0.1, collisions=1e6, batches=2, checkpoint=target)
    assert str(target) in str(e.value)
    with pytest.raises(OSError) as e:
        lg.report(tmp_path / "missing.json")
    assert "missing.json" in str(e.value)


def test_events_refuses_more_than_memory_holds():
    with pytest.raises(MemoryError, match="ask for at most"):
        lg.events(w=0.1, n=2**31)
    with pytest.raises(ValueError, match="out of range"):
        lg.events(w=0.1, n=0)


@pytest.mark.parametrize(
    "kwargs, args",
    [
        (dict(w=0.2), ["--w", "0.2"]),
        (dict(w=0.5, batches=8), ["--w", "0.5", "--batches", "8"]),
        (dict(w=0.5, msd_fit=(16, 99999)), ["--w", "0.5", "--msd-fit", "16:99999"]),
        (dict(scene="square", radius="1/2"), ["--scene", "square", "--radius", "1/2"]),
    ],
)
def test_superdiffusion_refusals_are_the_command_lines_line(cli, kwargs, args):
    with pytest.raises(ValueError) as e:
        lg.superdiffusion(**kwargs)
    line = cli_message(cli, "superdiffusion", *args)
    msg = str(e.value)
    assert "\n" not in msg
    assert line.endswith(msg.split(": ", 1)[-1]) or line == "error: " + msg, (line, msg)


def test_a_value_out_of_range_is_named_as_each_front_end_spells_it(cli):
    # One typed error: Python names the keyword (points_per_octave=17), the command line the
    # flag (--points-per-octave 17), and both give the same range.
    with pytest.raises(ValueError) as e:
        lg.superdiffusion(w=0.5, points_per_octave=17)
    assert str(e.value) == "points_per_octave=17 is out of range: use 1 to 16"
    line = cli_message(cli, "superdiffusion", "--w", "0.5", "--points-per-octave", "17")
    assert line == "error: --points-per-octave 17 is out of range: use 1 to 16"


def test_an_option_an_analysis_does_not_use_is_refused():
    # Lyapunov exponents keep no checkpoint: the keyword is not there to be ignored.
    with pytest.raises(TypeError, match="checkpoint"):
        lg.lyapunov(w=0.1, checkpoint="run.ckpt")
    with pytest.raises(TypeError, match="engine"):
        lg.escape(w=0.1, engine="scalar")

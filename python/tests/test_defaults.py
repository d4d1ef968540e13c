"""Every keyword's default is the command line's default for the same option (parsed from
`lorentz <command> --help`), so that a call with defaults and the bare command agree."""

import inspect
import json
import re

import pytest

import lorentz_gas as lg

FUNCTIONS = ["diffusion", "hops", "theory", "lattice_walk", "backscatter", "sweep", "escape", "lyapunov", "superdiffusion", "free_paths", "audit",
             "shadow", "certify", "cycles", "trajectory", "report", "bench"]
# Python keywords that are not command-line options (or are one under another name).
NOT_OPTIONS = {"w", "progress", "path", "start", "direction", "time", "events", "scene",
               "radius", "out", "widths", "threads", "max_rerun_collisions", "checkpoint",
               "w_from", "w_to", "window", "check_window", "audit", "vacf_fit", "msd_fit"}


def cli_defaults(cli, command):
    code, text, err = cli(command, "--help")
    assert code == 0, err
    defaults = {}
    # One block per option: its header line and the description under it (which clap may wrap
    # anywhere, "[default: ...]" included).
    blocks = re.split(r"\n(?=\s+(?:-\w, )?--[\w-]+)", text)
    for block in blocks:
        m = re.match(r"\s+(?:-\w, )?--([\w-]+)", block)
        d = re.search(r"\[default:\s*([^\]]+)\]", block)
        if m and d:
            defaults[m.group(1).replace("-", "_")] = " ".join(d.group(1).split())
    return defaults


def as_cli_text(v):
    if isinstance(v, float) and v.is_integer():
        return str(int(v))
    return str(v)


def as_number(text):
    try:
        return float(text.replace("_", ""))
    except ValueError:
        return text


@pytest.mark.parametrize("name", FUNCTIONS)
def test_defaults_are_the_command_lines(cli, name):
    cli_d = cli_defaults(cli, name.replace("_", "-"))
    checked = 0
    for p in inspect.signature(getattr(lg, name)).parameters.values():
        if p.default is inspect.Parameter.empty or p.name in NOT_OPTIONS:
            continue
        if p.default is False:
            continue  # a flag, off unless given
        if p.default is None:
            continue  # an option without a default: absent unless given
        assert p.name in cli_d, f"{name}({p.name}=...) has no command-line default ({sorted(cli_d)})"
        assert as_number(as_cli_text(p.default)) == as_number(cli_d[p.name]), (
            f"{name}: {p.name} = {p.default!r} in Python, {cli_d[p.name]} on the command line"
        )
        checked += 1
    # cycles: every default depends on the table (the repeller's or, with w, the lattice's).
    assert checked > 0 or name in ("trajectory", "cycles")


def test_windows_default_to_the_command_lines(cli):
    d = cli_defaults(cli, "diffusion")
    sig = inspect.signature(lg.diffusion).parameters
    for k in ["window", "check_window"]:
        lo, hi = sig[k].default
        assert f"{lo}:{hi}" == d[k]
    # Superdiffusion's windows follow the octaves on both sides: no fixed default, and the same
    # windows chosen at 6 octaves.
    d = cli_defaults(cli, "superdiffusion")
    sig = inspect.signature(lg.superdiffusion).parameters
    for k in ["vacf_fit", "msd_fit"]:
        assert sig[k].default is None and k not in d
    py = lg.superdiffusion(radius="1/4", scene="square", collisions=3.2e6, batches=16, octaves=6)
    code, out, err = cli("superdiffusion", "--scene", "square", "--radius", "1/4",
                         "--collisions", "3.2e6", "--batches", "16", "--octaves", "6", "--json")
    assert code == 0, err
    cl = json.loads(out)
    assert [py.vacf_fit.tolist(), py.msd_fit.tolist()] == [cl["vacf_fit"], cl["msd_fit"]]

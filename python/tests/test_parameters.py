"""Each parameter in every front end: every field of an analysis's configuration (as its result
records it: the library's one description of the run) is an option of the command line, a keyword
of the Python function and a parameter of the compiled function's type stub; and the stubs are the
compiled module's real signatures. A field added to a config and forgotten in one of them fails
here."""

import ast
import inspect
import pathlib
import re
import tempfile

import pytest

import lorentz_gas as lg
from lorentz_gas import _native

STUBS = pathlib.Path(lg.__file__).with_name("_native.pyi")

# A result of each analysis that records its configuration, at small statistics.
CASES = {
    "diffusion": ["--w", "0.2", "--collisions", "1e6", "--batches", "4"],
    "diffusion --field": ["--w", "0.2", "--collisions", "1e6", "--batches", "4", "--field", "1",
                          "--localization-samples", "1000"],
    "hops": ["--w", "0.2", "--collisions", "1e6", "--batches", "4"],
    "theory": ["--w", "0.2", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    "lattice_walk": ["--w", "0.2", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    "backscatter": ["--w", "0.2", "--particles", "1e3", "--batches", "4"],
    "audit": ["--w", "0.2", "--collisions", "1e3", "--batches", "2"],
    "shadow": ["--w", "0.2", "--collisions-per-segment", "20", "--segments", "1"],
    "shadow --field": ["--w", "0.2", "--collisions-per-segment", "20", "--segments", "1",
                       "--field", "1"],
    "escape": ["--w", "0.2", "--particles-per-width", "3200"],
    "sweep --fields": ["--w", "0.2", "--fields=-1,1", "--collisions-per-run", "1e6",
                       "--batches-per-run", "4", "--localization-samples", "1000",
                       "--out", tempfile.mkdtemp(prefix="lorentz-test-")],
}

# The compiled function behind a case, where it is not the Python function's own name.
STUB_OF = {"sweep --fields": "field_sweep"}

# Config fields that are not parameters of the call, with the reason. Every entry must name a
# field the config has (a stale entry fails too).
NOT_PARAMETERS = {
    ("diffusion", "w_exact"): "the gap as typed: given as w",
    ("backscatter", "w_exact"): "the gap as typed: given as w",
    ("diffusion", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("diffusion --field", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("hops", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("backscatter", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("theory", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("lattice_walk", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("audit", "scene"): "the scene's label, from scene, w and radius",
    ("sweep --fields", "gaps"): "the exact grid of gaps: from w, or w_from, w_to and steps",
}


def cli_options(cli, command):
    code, text, err = cli(command, "--help")
    assert code == 0, err
    return {m.replace("-", "_") for m in re.findall(r"^\s+(?:-\w, )?--([\w-]+)", text, re.M)}


def stub_parameters():
    """Each stub's parameters: a function's, or a class's constructor's (without self)."""
    tree = ast.parse(STUBS.read_text())
    out = {f.name: [a.arg for a in f.args.args] for f in tree.body if isinstance(f, ast.FunctionDef)}
    for c in tree.body:
        if isinstance(c, ast.ClassDef):
            init = [f for f in c.body if isinstance(f, ast.FunctionDef) and f.name == "__init__"]
            if init:
                out[c.name] = [a.arg for a in init[0].args.args][1:]
    return out


def compiled_parameters(name):
    sig = getattr(_native, name).__text_signature__
    assert sig, f"_native.{name} has no text signature"
    return [p.split("=")[0].strip() for p in sig.strip("()").split(",") if p.strip() and p.strip() != "$module"]


@pytest.mark.parametrize("name", sorted(CASES))
def test_every_config_field_is_a_parameter_everywhere(cli_json, cli, name):
    function = name.split()[0]
    command = function.replace("_", "-")
    config = cli_json(command, *CASES[name])["config"]
    fields = set(config)
    stale = {f for (n, f) in NOT_PARAMETERS if n == name} - fields
    assert not stale, f"{name}: NOT_PARAMETERS names fields the config does not have: {stale}"
    fields -= {f for (n, f) in NOT_PARAMETERS if n == name}
    options = cli_options(cli, command)
    keywords = set(inspect.signature(getattr(lg, function)).parameters)
    stub = set(stub_parameters()[STUB_OF.get(name, function)])
    for where, have in [("the command line", options), ("lorentz_gas." + function, keywords),
                        ("the stub _native." + function, stub)]:
        missing = sorted(fields - have)
        assert not missing, f"{name}: config fields missing from {where}: {missing}"


def test_the_stubs_are_the_compiled_signatures():
    stubs = stub_parameters()
    compiled = {n for n in dir(_native) if callable(getattr(_native, n))
                and getattr(getattr(_native, n), "__text_signature__", None)}
    assert compiled, "no compiled function has a text signature"
    for name in sorted(compiled):
        assert name in stubs, f"_native.{name} has no stub"
        assert stubs[name] == compiled_parameters(name), (name, stubs[name], compiled_parameters(name))
    extra = sorted(set(stubs) - compiled)
    assert not extra, f"stubs of functions the module does not have: {extra}"

"""Each parameter in every front end: every field of an analysis's configuration (as its result
records it: the library's one description of the run) is an option of the command line, a keyword
of the Python function, a key the compiled function reads and a key of its type stub; the keyword
parameters of every public analysis are exactly the keys its compiled functions read
(`_native.parameters`); and the stubs are the compiled module's real signatures. A field added to
a config and forgotten in one of them, or a key the Python and Rust sides disagree on, fails
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
    "diffusion --electric": ["--w", "0.2", "--collisions", "2e5", "--batches", "4",
                             "--electric", "1/2", "--electric-angle", "30"],
    "hops": ["--w", "0.2", "--collisions", "1e6", "--batches", "4"],
    "theory": ["--w", "0.2", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    "lattice_walk": ["--w", "0.2", "--collisions", "1e6", "--batches", "4", "--order", "2"],
    "backscatter": ["--w", "0.2", "--particles", "1e3", "--batches", "4"],
    "audit": ["--w", "0.2", "--collisions", "1e3", "--batches", "2"],
    "shadow": ["--w", "0.2", "--collisions-per-segment", "20", "--segments", "1"],
    "shadow --field": ["--w", "0.2", "--collisions-per-segment", "20", "--segments", "1",
                       "--field", "1"],
    "escape": ["--w", "0.2", "--particles-per-width", "3200"],
    "escape --repeller": ["--repeller", "--particles", "1e6"],
    "cycles": ["--max-length", "2"],
    "cycles --w": ["--w", "1/10", "--max-length", "2", "--msd-collisions", "0"],
    "section": ["--w", "0.2", "--field", "5/2", "--trajectories", "4", "--collisions", "100",
                "--classify-collisions", "1000"],
    "sweep --fields": ["--w", "0.2", "--fields=-1,1", "--collisions-per-run", "1e6",
                       "--batches-per-run", "4", "--localization-samples", "1000",
                       "--out", tempfile.mkdtemp(prefix="lorentz-test-")],
    "sweep --electric": ["--w", "0.2", "--electric=-1/10,1/10", "--collisions-per-run", "2e5",
                         "--batches-per-run", "4",
                         "--out", tempfile.mkdtemp(prefix="lorentz-test-")],
}

# The compiled function behind a case, where it is not the Python function's own name.
STUB_OF = {
    "sweep --fields": "field_sweep",
    "sweep --electric": "driven_sweep",
    "escape --repeller": "survival",
    "cycles --w": "lattice_cycles",
}

# Config fields that are not parameters of the call, with the reason. Every entry must name a
# field the config has (a stale entry fails too).
NOT_PARAMETERS = {
    ("diffusion", "w_exact"): "the gap as typed: given as w",
    ("backscatter", "w_exact"): "the gap as typed: given as w",
    ("hops", "w_exact"): "the gap as typed: given as w",
    ("theory", "w_exact"): "the gap as typed: given as w",
    ("lattice_walk", "w_exact"): "the gap as typed: given as w",
    ("escape", "w_exact"): "the gap as typed: given as w",
    ("escape --repeller", "scene"): "the open table: from repeller, side and radius, or open_table",
    ("diffusion", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("diffusion --field", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("diffusion --electric", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("hops", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("backscatter", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("theory", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("lattice_walk", "run"): "which run of a seed: set by sweeps, not by a caller",
    ("audit", "scene"): "the scene's label, from scene, w and radius",
    ("sweep --fields", "gaps"): "the exact grid of gaps: from w, or w_from, w_to and steps",
    ("sweep --electric", "gaps"): "the one gap: given as w",
}


def cli_options(cli, command):
    code, text, err = cli(command, "--help")
    assert code == 0, err
    return {m.replace("-", "_") for m in re.findall(r"^\s+(?:-\w, )?--([\w-]+)", text, re.M)}


def stub_params_keys():
    """The keys of each stub's ``params`` dict (its TypedDict's fields, with those it inherits)."""
    tree = ast.parse(STUBS.read_text())
    classes = {c.name: c for c in tree.body if isinstance(c, ast.ClassDef)}

    def fields(name):
        c = classes[name]
        own = [a.target.id for a in c.body if isinstance(a, ast.AnnAssign)]
        inherited = [f for b in c.bases if isinstance(b, ast.Name) and b.id in classes
                     for f in fields(b.id)]
        return inherited + own

    # Each function, and each class by its constructor.
    functions = [(f.name, f) for f in tree.body if isinstance(f, ast.FunctionDef)]
    functions += [(c.name, f) for c in classes.values() for f in c.body
                  if isinstance(f, ast.FunctionDef) and f.name == "__init__"]
    out = {}
    for name, f in functions:
        params = [a for a in f.args.args if a.arg == "params"]
        if params:
            out[name] = fields(params[0].annotation.id)
    return out


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
    native = STUB_OF.get(name, function)
    stub = set(stub_params_keys()[native])
    read = set(_native.parameters(native))
    for where, have in [("the command line", options), ("lorentz_gas." + function, keywords),
                        ("the keys _native." + native + " reads", read),
                        ("the stub _native." + native, stub)]:
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


# The compiled functions behind each public analysis (the keys they read together are the
# function's keyword parameters).
NATIVES = {
    "diffusion": ["diffusion"],
    "hops": ["hops"],
    "theory": ["theory"],
    "lattice_walk": ["lattice_walk"],
    "backscatter": ["backscatter"],
    "sweep": ["sweep", "field_sweep", "driven_sweep"],
    "merge": ["merge"],
    "escape": ["escape", "survival"],
    "lyapunov": ["lyapunov"],
    "superdiffusion": ["superdiffusion"],
    "free_paths": ["free_paths"],
    "audit": ["audit"],
    "shadow": ["shadow"],
    "certify": ["certify"],
    "cycles": ["cycles", "lattice_cycles"],
    "trajectory": ["trajectory"],
    "section": ["section"],
    "constants": ["constants"],
    "report": ["report"],
    "figure": ["figure"],
    "reproduce": ["reproduce"],
    "bench": ["bench", "bench_long_flights"],
    "events": ["EventStream"],
    "Trajectory": ["EventStream"],
}

# Keyword parameters the Python wrapper consumes itself, with the reason.
PYTHON_ONLY = {
    "progress": "the progress bar or callback (`_progress._Bar`), passed beside the dict",
    ("events", "n"): "the events asked for: passed to EventStream.next, not to the constructor",
    ("escape", "repeller"): "picks the open table's compiled survival (with side and radius)",
    ("sweep", "executor"): "the pool the points are spread over: each call is the compiled sweep",
}

# Public functions that are not analyses, with the reason.
NOT_ANALYSES = {
    "agreement_bound": "a closed form of one number (`_native.agreement_bound(dof)`)",
    "draw_lattice": "pure Python (matplotlib)",
    "lattice_disks": "pure Python (the disks of a scene that reach into a box, for drawing)",
    "load": "pure Python (a result file read back into its result object)",
    "arcs": "pure Python (the flights of an events array, with their circles in a field)",
    "draw_events": "pure Python (matplotlib)",
}


def python_keywords(name):
    f = getattr(lg, name)
    sig = inspect.signature(f.__init__ if inspect.isclass(f) else f)
    return {k for k in sig.parameters
            if k not in ("self", "progress") and (name, k) not in PYTHON_ONLY}


@pytest.mark.parametrize("name", sorted(NATIVES))
def test_the_keywords_are_exactly_the_keys_the_compiled_functions_read(name):
    keywords = python_keywords(name)
    read = [set(_native.parameters(n)) for n in NATIVES[name]]
    for native, keys in zip(NATIVES[name], read):
        extra = sorted(keys - keywords)
        assert not extra, f"_native.{native} reads keys lorentz_gas.{name} does not take: {extra}"
    missing = sorted(keywords - set().union(*read))
    assert not missing, f"lorentz_gas.{name} takes keywords no compiled function reads: {missing}"


def test_every_public_function_and_every_compiled_analysis_is_checked():
    public = {n for n in lg.__all__ if callable(getattr(lg, n))
              and not (inspect.isclass(getattr(lg, n)) and n != "Trajectory")}
    unchecked = sorted(public - set(NATIVES) - set(NOT_ANALYSES))
    assert not unchecked, f"public functions neither in NATIVES nor in NOT_ANALYSES: {unchecked}"
    stale = sorted((set(NATIVES) | set(NOT_ANALYSES)) - public)
    assert not stale, f"NATIVES or NOT_ANALYSES name what lorentz_gas does not export: {stale}"
    taking_params = set(stub_params_keys())
    behind = {n for natives in NATIVES.values() for n in natives}
    assert taking_params == behind, (sorted(taking_params - behind), sorted(behind - taking_params))


@pytest.mark.parametrize("name", sorted(stub_params_keys()))
def test_the_stubs_params_are_the_keys_read(name):
    assert sorted(stub_params_keys()[name]) == sorted(_native.parameters(name)), name


def test_a_key_not_read_or_missing_is_refused_naming_it():
    good = {"w": "0.1", "radius": None, "precision": "f64"}
    assert _native.constants(good)[0]
    with pytest.raises(ValueError, match="unknown parameter `colour`"):
        _native.constants({**good, "colour": "blue"})
    with pytest.raises(ValueError, match="missing parameter `precision`"):
        _native.constants({"w": "0.1", "radius": None})
    with pytest.raises(ValueError, match=r"precision="):
        _native.constants({**good, "precision": 53})
    with pytest.raises(ValueError, match="no analysis named"):
        _native.parameters("difusion")
    # Refused before any work, for every analysis.
    for name in stub_params_keys():
        native = getattr(_native, name)
        args = ({"unread": 1},) if name in ("constants", "EventStream") else ({"unread": 1}, None)
        with pytest.raises(ValueError, match="missing parameter"):
            native(*args)


class _Handed(Exception):
    """Raised by a stand-in compiled function once it has recorded its request."""


def handed_request(monkeypatch, name, **kwargs):
    """The request ``lorentz_gas.<name>(**kwargs)`` hands to its compiled function: each
    compiled function of the analysis is replaced by one that records its request and stops."""
    seen = {}

    def stand_in(native):
        def record(request, *rest):
            seen[native] = dict(request)
            raise _Handed
        return record

    for native in NATIVES[name]:
        monkeypatch.setattr(_native, native, stand_in(native))
    with pytest.raises(_Handed):
        getattr(lg, name)(**kwargs)
    assert len(seen) == 1, seen
    return seen


# Values of common keywords, two each: a call with one of them that differs from the default
# must hand a different request on.
VALUES = {
    "engine": ["scalar", "simd"],
    "seed": [3, 7],
    "threads": [1, 2],
    "batches": [3, 5],
    "collisions": [10_000, 20_000],
    "precision": ["f64", 128],
}

# Analyses whose every call needs more than w (a result to read, a table to draw): left to their
# own tests.
NEEDS_MORE = {"merge", "report", "figure", "reproduce", "events", "Trajectory", "trajectory",
              "constants"}


def forwarding_cases():
    cases = []
    for name in sorted(set(NATIVES) - NEEDS_MORE):
        params = inspect.signature(getattr(lg, name)).parameters
        for key, values in VALUES.items():
            if key in params:
                cases.append((name, key))
    return cases


@pytest.mark.parametrize("name,key", forwarding_cases())
def test_every_common_keyword_reaches_the_compiled_function(monkeypatch, name, key):
    """A keyword the wrapper takes but drops (a dict entry forgotten, or the default written in
    its place) passes the name checks above; here a value other than the default must change
    the request the compiled function is handed."""
    params = inspect.signature(getattr(lg, name)).parameters
    # The gap wherever it may be given (where it may also be left out, a run on its table); a
    # sweep over w by its ends.
    if name == "sweep":
        base = {"w_from": "0.1", "w_to": "0.2", "steps": 2}
    elif "w" in params and params["w"].default in (inspect.Parameter.empty, None):
        base = {"w": "0.2"}
    else:
        base = {}
    default = params[key].default
    value = next(v for v in VALUES[key] if v != default)
    before = handed_request(monkeypatch, name, **base)
    after = handed_request(monkeypatch, name, **base, **{key: value})
    assert before.keys() == after.keys(), (before.keys(), after.keys())
    (native,) = before
    assert before[native] != after[native], (
        f"lorentz_gas.{name}({key}={value!r}) hands _native.{native} the request of the default"
    )


def test_the_forwarding_test_covers_the_analyses_that_run_on_an_engine():
    covered = {(n, k) for n, k in forwarding_cases()}
    for name in ["diffusion", "hops", "sweep", "bench"]:
        assert (name, "engine") in covered, name
    for name in ["diffusion", "hops", "theory", "lattice_walk", "backscatter", "lyapunov"]:
        assert (name, "seed") in covered, name

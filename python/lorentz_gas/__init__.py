"""Deterministic diffusion in the two-dimensional periodic Lorentz gas.

A point particle of speed 1 among hard disks of radius 1 on a triangular lattice of spacing
2 + w (Klages & Dellago, J. Stat. Phys. 101, 145 (2000)), or among disks of radius r at the
integer points of the plane (the square scene). Every function runs the ``lorentz-gas`` Rust
library and returns what ``lorentz <command> --json`` prints, with the same bits for the same
parameters and seed. Lengths are in units of the disk radius (triangular) or of the lattice
spacing (square); times in those units over the speed 1.

Inputs
    Gaps and radii: a ``str`` (an exact decimal ``"0.1"`` or fraction ``"1/10"``, parsed as the
    command line parses it), a ``fractions.Fraction`` or ``decimal.Decimal`` (exact), or a
    ``float`` (taken as its shortest decimal, ``0.1`` as ``"0.1"``). Counts: an ``int``, a
    whole ``float`` (``2e9``) or a string (``"2e9"``, ``"2_000_000_000"``).

Behaviour
    The GIL is released while computing; Ctrl-C (``KeyboardInterrupt``) stops a run within
    about a second (certify, trajectory, shadow and report finish first) and leaves no thread
    behind; ``progress=True`` shows a tqdm bar when tqdm is
    installed (or pass a callable receiving the units done since its last call). Bad input
    raises ``ValueError`` with the command line's one-line message naming the valid range; I/O
    problems raise ``OSError`` naming the path.

Example
    >>> import lorentz_gas as lg
    >>> r = lg.diffusion(w=0.1, collisions=2e7, batches=8)   # doctest: +SKIP
    >>> r                                                     # doctest: +SKIP
    <DiffusionResult: D = 0.0998... ± 0.000... at w = 0.1>
"""

from __future__ import annotations

import decimal
import difflib
import fractions
import functools
import inspect
import numbers
import os
from typing import Any, Callable, Dict, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._native import CheckFailedError, ComputationError
from ._results import (
    AuditResult,
    BackscatterResult,
    BenchResult,
    CertifyResult,
    ConstantsResult,
    ConstantsTable,
    DiffusionResult,
    EscapeResult,
    FieldResult,
    HopsResult,
    LatticeWalkResult,
    LyapunovResult,
    ReportResult,
    Result,
    ShadowResult,
    SuperdiffusionResult,
    SweepResult,
    FieldSweepResult,
    TheoryResult,
    TrajectoryResult,
)

from ._drawing import draw_lattice, lattice_disks

__version__ = _native.__version__

__all__ = [
    "diffusion",
    "hops",
    "theory",
    "lattice_walk",
    "backscatter",
    "sweep",
    "escape",
    "lyapunov",
    "superdiffusion",
    "audit",
    "shadow",
    "certify",
    "trajectory",
    "constants",
    "report",
    "events",
    "bench",
    "Trajectory",
    "draw_lattice",
    "lattice_disks",
    "EVENT_DTYPE",
    "agreement_bound",
    "Result",
    "ConstantsResult",
    "ConstantsTable",
    "DiffusionResult",
    "FieldResult",
    "HopsResult",
    "TheoryResult",
    "LatticeWalkResult",
    "BackscatterResult",
    "SuperdiffusionResult",
    "SweepResult",
    "FieldSweepResult",
    "EscapeResult",
    "LyapunovResult",
    "AuditResult",
    "ShadowResult",
    "CertifyResult",
    "TrajectoryResult",
    "BenchResult",
    "ReportResult",
    "CheckFailedError",
    "ComputationError",
]

Exact = Union[str, float, int, fractions.Fraction, decimal.Decimal]
Count = Union[int, float, str]
Progress = Union[None, bool, Callable[[int], Any]]
PathLike = Union[str, "os.PathLike[str]"]

#: The dtype of :func:`events`: one record per event.
EVENT_DTYPE = np.dtype(
    [
        ("t", np.float64),  # time since the start (speed 1: also the path length)
        ("x", np.float64),  # unwrapped world position after the event
        ("y", np.float64),
        ("vx", np.float64),  # velocity after the event (unit length)
        ("vy", np.float64),
        ("kind", "U9"),  # "start" (the first row), "collision" (with a disk) or "crossing" (an edge)
        ("collision", np.bool_),  # True: a collision with a disk; False: a crossing or the start
        ("obstacle", np.uint8),  # the disk (collision) or edge (crossing) label; 255 at the start
        ("i", np.int64),  # cell indices along the lattice vectors e1, e2
        ("j", np.int64),
        ("down", np.bool_),  # the cell's orientation (triangular lattice: a point-reflected trap)
    ]
)


def agreement_bound(dof: float) -> float:
    """The crate's agreement bound for a value with an error from ``dof + 1`` batches: the
    Student-t quantile with ``dof`` degrees of freedom whose two-sided tail equals that of 4
    normal sigma (6.3e-5); ``agreement_bound(float("inf"))`` is 4 to 11 digits."""
    return _native.agreement_bound(float(dof))


def _exact(name: str, v: Any) -> str:
    """An exact input as the text the command line parses."""
    if isinstance(v, bool):
        raise TypeError(f"{name} must be a number or a string, not bool")
    if isinstance(v, str):
        return v
    if isinstance(v, fractions.Fraction):
        return f"{v.numerator}/{v.denominator}"
    if isinstance(v, decimal.Decimal):
        return str(v)
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        _refuse_lossy(name, v)
        return repr(float(v))
    raise TypeError(f"{name} must be a str, float, int, Fraction or Decimal, not {type(v).__name__}")


def _refuse_lossy(name: str, v: Any) -> None:
    """Refuses a float narrower than a double (numpy.float32 0.1 is 0.100000001490116...: the
    decimal meant is already lost) or one a double cannot hold (numpy.longdouble)."""
    if isinstance(v, float):
        return
    size = getattr(getattr(v, "dtype", None), "itemsize", 8)
    if size < 8:
        raise ValueError(
            f"{name} = {type(v).__name__}({v!r}) holds {float(v)!r}, not the decimal it was "
            f"written as: a {8 * size}-bit float has lost it; pass a str such as '0.1', a Python "
            "float, a Fraction or a Decimal"
        )
    if float(v) != v:
        raise ValueError(
            f"{name} = {type(v).__name__}({v!r}) is not a double: it would be rounded; pass a str, "
            "a Fraction or a Decimal to give it exactly"
        )


def _optional_exact(name: str, v: Any) -> Optional[str]:
    return None if v is None else _exact(name, v)


def _window(name: str, v: Any) -> Tuple[float, float]:
    """A window (from, to) of two numbers."""
    try:
        lo, hi = v
        return (float(lo), float(hi))
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"{name}: {v!r} is not a window (from, to): use two numbers such as (64, 256)"
        ) from e


def _count(name: str, v: Any) -> str:
    """A count as the text the command line parses (whole floats such as 2e9 are accepted)."""
    if isinstance(v, bool):
        raise TypeError(f"{name} must be a whole number, not bool")
    if isinstance(v, str):
        return v
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        return repr(int(f)) if f.is_integer() and abs(f) < 2.0**64 else repr(f)
    raise TypeError(f"{name} must be an int, a whole float or a string, not {type(v).__name__}")


def _threads(v: Optional[Count]) -> Optional[str]:
    return None if v is None else _count("threads", v)


def _path(v: Optional[PathLike]) -> Optional[str]:
    return None if v is None else os.fspath(v)


def _in_notebook() -> bool:
    """Whether the caller runs in a Jupyter kernel (where a bar is wanted by default)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


class _Bar:
    """A tqdm bar fed by the run's progress (nothing when tqdm is missing)."""

    def __init__(self, progress: Progress, total: Optional[float], unit: str):
        self.bar = None
        self.callback: Optional[Callable[[int], Any]] = None
        if progress is None:
            progress = _in_notebook()
        if callable(progress):
            self.callback = progress
        elif progress:
            try:
                import ipywidgets  # noqa: F401  (tqdm's notebook bar needs it)
                from tqdm.auto import tqdm
            except ImportError:
                try:
                    from tqdm import tqdm
                except ImportError:
                    return
            self.bar = tqdm(
                total=None if total is None else int(total),
                unit=unit,
                unit_scale=True,
                dynamic_ncols=True,
            )
            self.callback = self.bar.update

    def __enter__(self) -> Optional[Callable[[int], Any]]:
        return self.callback

    def __exit__(self, *exc: Any) -> None:
        if self.bar is not None:
            self.bar.close()


def _total(v: Any) -> float:
    try:
        return float(str(v).replace("_", ""))
    except ValueError:
        return 0.0


def diffusion(
    w: Exact,
    collisions: Optional[Count] = None,
    batches: Count = 32,
    seed: Count = 1,
    threads: Optional[Count] = None,
    engine: str = "auto",
    precision: Union[str, int] = "f64",
    window: Tuple[float, float] = (10, 40),
    check_window: Tuple[float, float] = (20, 80),
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    audit: Optional[float] = None,
    reference_bits: Count = 128,
    field: Optional[Exact] = None,
    localization_samples: Count = 1_000_000,
    progress: Progress = None,
    *,
    rel_err: Optional[float] = None,
) -> Union[DiffusionResult, FieldResult]:
    """The diffusion coefficient D(w) by the Einstein formula (``lorentz diffusion``), or with a
    magnetic ``field`` the diffusion tensor (``lorentz diffusion --field``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap between neighbouring disks (radius 1): 0 < w < w_inf = 4/sqrt(3) - 2 = 0.3094...
    collisions : int, optional
        Collisions in all, over every batch (at least 2 per batch); default 2e9. With
        ``rel_err``, the pilot's collisions (default 2e8).
    batches : int
        Independent trajectories, at least 2; ``D_err`` is their standard error.
    seed : int
        Seed of the random starts: the same seed gives the same bits on any thread count,
        engine, or in the command line.
    threads : int, optional
        Worker threads, 1 to 4 per core (default: every core this process may use).
    engine : {"auto", "scalar", "simd"}
        The engine; every engine gives the same bits.
    precision : "f64" or int
        The number type: f64, or MPFR with this many bits (53 or more; much slower).
    window, check_window : (lo, hi)
        Fit windows of the MSD slope, in units of the mean hop time tau.
    checkpoint : path, optional
        Keep the work in this file; a rerun with the same parameters resumes to the same bits.
    checkpoint_every : float
        Seconds between saves of the trajectories in flight (0 to 86400).
    audit : float, optional
        Replay this fraction (0, 1] of the events in MPFR as the run goes (f64 runs).
    reference_bits : int
        MPFR precision of the audit's replay (128 to 65536 bits).
    field : str, float, Fraction or Decimal, optional
        A uniform magnetic field B (1/length at speed 1) perpendicular to the plane, taken
        exactly like ``w``: the velocity turns at the angular velocity B, counter-clockwise for
        B > 0, on a cyclotron circle of radius 1/abs(B); 1e-3 <= abs(B) <= 1e3. ``None`` or 0: the
        run without a field (its own bits). A field run takes no checkpoint or audit and runs
        on the scalar engine.
    localization_samples : int
        With ``field``: phase points classified for the sampled share of localized orbits.
    progress : bool, callable or None
        Show a tqdm bar (if tqdm is installed), or call ``progress(n)`` with collisions done.
        ``None`` (the default): a bar in a Jupyter notebook, none in scripts; ``False``: none.
    rel_err : float, optional
        Stop at this relative error of D (``1e-4`` is 0.01 %, from 1e-7 to 0.5): a pilot of
        ``collisions`` measures how the error falls with the collisions, then the run of the
        size it plans runs (the bits of a plain run of that size, resumable with
        ``checkpoint``); ``pilot`` in the result records the pilot. The error reached scatters
        by about 13 % about the target with 32 batches (the pilot's error is itself estimated).

    Returns
    -------
    DiffusionResult
        ``D``, ``D_err`` (length^2/time), ``D_check``, ``D_check_err``, ``mean_free_path``,
        ``mean_free_path_err``, ``mean_free_path_exact``, ``msd_times``, ``msd`` and
        ``batch_D`` (numpy arrays), ``meta``; ``to_dict()``, ``to_json()``.
    FieldResult
        With a nonzero ``field``: ``D_xx``, ``D_xy`` (the Hall part) with ``_err`` over the whole
        phase space, ``diffusing`` (the tensor of the diffusing part), ``pinned_fraction_exact``,
        ``localized_fraction_exact``, ``localized_fraction`` ± ``localized_fraction_err``,
        ``mean_free_time`` against Kac's ``mean_free_time_exact``.
    """
    # A planned run's size is known only after its pilot: a bar without a total.
    total = None if rel_err is not None else _total(_count("collisions", 2e9 if collisions is None else collisions))
    with _Bar(progress, total, "coll") as cb:
        text = _native.diffusion(
            _exact("w", w),
            None if collisions is None else _count("collisions", collisions),
            _count("batches", batches),
            _count("seed", seed),
            _threads(threads),
            str(engine),
            str(precision),
            (float(window[0]), float(window[1])),
            (float(check_window[0]), float(check_window[1])),
            _path(checkpoint),
            float(checkpoint_every),
            None if audit is None else float(audit),
            _count("reference_bits", reference_bits),
            None if field is None else _exact("field", field),
            _count("localization_samples", localization_samples),
            cb,
            None if rel_err is None else float(rel_err),
        )
    if '"D_xy"' in text:
        return FieldResult(text)
    return DiffusionResult(text)


def hops(
    w: Exact,
    collisions: Count = 2e8,
    batches: Count = 16,
    order: Count = 4,
    seed: Count = 1,
    threads: Optional[Count] = None,
    engine: str = "auto",
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
) -> HopsResult:
    """Trap-hopping statistics along lattice trajectories (``lorentz hops``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap between neighbouring disks (radius 1): 0 < w < w_inf = 0.3094...
    collisions : int
        Lorentz-gas collisions in all, over every batch.
    batches : int
        Independent trajectories, at least 2; every error bar is over them.
    order : int
        Longest symbol sequence counted (1 to 7).
    seed, threads, engine, checkpoint, checkpoint_every, progress
        As in :func:`diffusion`.

    Returns
    -------
    HopsResult
        ``p_bs`` (backscattering probability, dimensionless) ± ``p_bs_err``, the symbol-sequence
        probabilities ``pairs`` with ``pairs_err``, the symmetry test (``symmetry_max_z``
        against ``symmetry_bound``) and the hop-level Green–Kubo ``D_GK`` ± ``D_GK_err``
        (length^2/time) against ``D_MZ``.
    """
    with _Bar(progress, _total(_count("collisions", collisions)), "coll") as cb:
        text = _native.hops(
            _exact("w", w),
            _count("collisions", collisions),
            _count("batches", batches),
            _count("order", order),
            _count("seed", seed),
            _threads(threads),
            str(engine),
            _path(checkpoint),
            float(checkpoint_every),
            cb,
        )
    return HopsResult(text)


def theory(
    w: Exact,
    collisions: Count = 2e8,
    batches: Count = 16,
    order: Count = 4,
    seed: Count = 1,
    threads: Optional[Count] = None,
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
) -> TheoryResult:
    """The corrected Machta–Zwanzig hierarchy on measured hop statistics (``lorentz theory``).

    Parameters
    ----------
    w, collisions, batches, seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`hops`.
    order : int
        Longest symbol sequence counted, and highest order of the hierarchy (1 to 7).

    Returns
    -------
    TheoryResult
        ``D_cf``, ``D_bs``, ``D_1`` and the orders ``D_k`` of the corrected hierarchy
        (length^2/time, each with its error), App. A's ``p_cf``, against ``D_GK`` and ``D_MZ``.
    """
    return TheoryResult(_hop_analysis(_native.theory, w, collisions, batches, order, seed,
                                      threads, checkpoint, checkpoint_every, progress))


def lattice_walk(
    w: Exact,
    collisions: Count = 2e8,
    batches: Count = 16,
    order: Count = 4,
    seed: Count = 1,
    threads: Optional[Count] = None,
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
) -> LatticeWalkResult:
    """Correlated lattice walks driven by the measured symbol tables (``lorentz lattice-walk``,
    Fig. 6b): walks of order 1 to ``order`` simulated, next to their exact D.

    Parameters
    ----------
    w, collisions, batches, order, seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`theory`.

    Returns
    -------
    LatticeWalkResult
        ``walks`` (one row per order: the simulated and the exact D, length^2/time) against the
        hop-level ``D_GK`` and ``D_MZ``.
    """
    return LatticeWalkResult(_hop_analysis(_native.lattice_walk, w, collisions, batches, order,
                                           seed, threads, checkpoint, checkpoint_every, progress))


def _hop_analysis(native, w, collisions, batches, order, seed, threads, checkpoint,
                  checkpoint_every, progress) -> str:
    with _Bar(progress, _total(_count("collisions", collisions)), "coll") as cb:
        return native(
            _exact("w", w),
            _count("collisions", collisions),
            _count("batches", batches),
            _count("order", order),
            _count("seed", seed),
            _threads(threads),
            _path(checkpoint),
            float(checkpoint_every),
            cb,
        )


def backscatter(
    w: Exact,
    particles: Count = 1e7,
    batches: Count = 32,
    seed: Count = 1,
    threads: Optional[Count] = None,
    precision: Union[str, int] = "f64",
    progress: Progress = None,
) -> BackscatterResult:
    """Backscattering by injection into one trap (``lorentz backscatter``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap, 0 < w < w_inf = 0.3094...
    particles : int
        Particles injected through the trap's openings with the invariant measure.
    batches : int
        Independent batches the particles are split into, at least 2 (the error bars).
    seed, threads, precision, progress
        As in :func:`diffusion`.

    Returns
    -------
    BackscatterResult
        The exit probabilities (dimensionless) with their standard errors, the mean time and
        collisions in the trap against their exact values.
    """
    with _Bar(progress, _total(_count("particles", particles)), "inj") as cb:
        text = _native.backscatter(
            _exact("w", w),
            _count("particles", particles),
            _count("batches", batches),
            _count("seed", seed),
            _threads(threads),
            str(precision),
            cb,
        )
    return BackscatterResult(text)


def sweep(
    w_from: Optional[Exact] = None,
    w_to: Optional[Exact] = None,
    steps: Count = 11,
    runs: Optional[Count] = None,
    collisions_per_run: Count = 2e8,
    batches_per_run: Count = 8,
    seed: Count = 1,
    threads: Optional[Count] = None,
    engine: str = "auto",
    out: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
    *,
    w: Optional[Exact] = None,
    field: Optional[Exact] = None,
    fields: Optional[Sequence[Exact]] = None,
    localization_samples: Count = 1e6,
) -> Union[SweepResult, FieldSweepResult]:
    """D(w) over a grid of gaps (``lorentz sweep``), or the diffusion tensor in a magnetic field
    over gaps and fields (``lorentz sweep --field`` / ``--fields``).

    Parameters
    ----------
    w_from, w_to : str, float, Fraction or Decimal
        First and last gap, each in 0 < w < w_inf = 0.3094...; the grid is computed exactly
        (0.1 .. 0.2 in 3 steps has 0.15, not its nearest double's neighbour).
    steps : int
        Number of gaps, at least 2.
    runs : int, optional
        Independent runs at each gap (default 10; their spread is checked against the batch
        errors). Not used in a field: one run per point.
    collisions_per_run : int
        Collisions of each run, over its batches (a point costs runs x this).
    batches_per_run : int
        Independent batches of each run, at least 2.
    out : path, optional
        Keep finished points there (a rerun resumes) and write sweep.csv, sweep-runs.csv,
        sweep.json and the figures (in a field: field-sweep.csv and field-sweep.json).
    seed, threads, engine, checkpoint_every, progress
        As in :func:`diffusion`.
    w : str, float, Fraction or Decimal, keyword only
        The gap of a sweep over the field (with ``fields``), instead of ``w_from``/``w_to``.
    field : exact number, keyword only
        A fixed field B (angular velocity of the velocity, 1/time; cyclotron radius 1/abs(B)) for
        a sweep over w.
    fields : sequence of exact numbers, keyword only
        The fields of a sweep over B (each nonzero, 1e-3 <= abs(B) <= 1e3); with B and -B both
        given, Onsager-Casimir is checked.
    localization_samples : int, keyword only
        Phase points classified per point for the sampled localized share.

    Returns
    -------
    SweepResult
        ``rows`` (numpy structured array, one record per gap: ``w``, ``D`` ± ``D_err`` in
        length^2/time, ``D_MZ``, ``D_Bo``, the runs' F test), the same fields as attributes,
        ``run_D`` (points x runs), ``linear_fit``; ``to_pandas()``.
    FieldSweepResult
        In a field: ``rows`` with ``w``, ``field``, ``D_xx`` ± ``D_xx_err``, the Hall ``D_xy`` ±
        ``D_xy_err`` (length^2/time), the exact and sampled localized shares and Kac's mean free
        time; ``onsager`` (the ±B checks) and ``onsager_agrees``; ``to_pandas()``.
    """
    if field is not None or fields is not None:
        if runs is not None:
            raise ValueError(
                "runs is not used by a sweep in a field (one run of collisions_per_run per point)"
            )
        if engine != "auto" or checkpoint_every != 60.0:
            raise ValueError(
                "engine and checkpoint_every are not used by a sweep in a field (the scalar arc "
                "kernel; a sweep in a field resumes by point from out)"
            )
        if fields is not None and (isinstance(fields, (str, bytes)) or not fields):
            raise ValueError("fields: give a non-empty sequence of exact numbers, e.g. [-1, 1]")
        total = _total(_count("collisions_per_run", collisions_per_run))
        total *= (1 if fields is None else len(fields)) * (
            1 if w is not None else _total(_count("steps", steps))
        )
        with _Bar(progress, total, "coll") as cb:
            text = _native.field_sweep(
                None if w is None else _exact("w", w),
                None if w_from is None else _exact("w_from", w_from),
                None if w_to is None else _exact("w_to", w_to),
                _count("steps", steps),
                None if field is None else _exact("field", field),
                [] if fields is None else [_exact("fields", b) for b in fields],
                _count("collisions_per_run", collisions_per_run),
                _count("batches_per_run", batches_per_run),
                _count("seed", seed),
                _threads(threads),
                _count("localization_samples", localization_samples),
                _path(out),
                cb,
            )
        return FieldSweepResult(text)
    if w is not None:
        raise ValueError(
            "w is the gap of a sweep over the field: give fields=[...] (a sweep over w: w_from, w_to)"
        )
    if w_from is None or w_to is None:
        raise ValueError("a sweep over w needs w_from and w_to")
    runs = 10 if runs is None else runs
    total = _total(_count("collisions_per_run", collisions_per_run)) * _total(
        _count("runs", runs)
    ) * _total(_count("steps", steps))
    with _Bar(progress, total, "coll") as cb:
        text = _native.sweep(
            _exact("w_from", w_from),
            _exact("w_to", w_to),
            _count("steps", steps),
            _count("runs", runs),
            _count("collisions_per_run", collisions_per_run),
            _count("batches_per_run", batches_per_run),
            _count("seed", seed),
            _threads(threads),
            str(engine),
            _path(out),
            float(checkpoint_every),
            cb,
        )
    return SweepResult(text)


def escape(
    w: Exact,
    widths: Optional[Sequence[float]] = None,
    particles_per_width: Count = 2e5,
    seed: Count = 1,
    threads: Optional[Count] = None,
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
) -> EscapeResult:
    """D from the escape rate out of open strips (``lorentz escape``, Gaspard–Baras).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap, 0 < w < w_inf = 0.3094...
    widths : sequence of float, optional
        At least 3 distinct strip widths L (lengths; default 8a, 12a, 16a, 24a with a = 2 + w),
        each at least max(4a, 10 mean free paths) and at most 2000.
    particles_per_width : int
        Particles injected into each strip, split into the batches the error bars are over.
    seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`diffusion`.

    Returns
    -------
    EscapeResult
        ``D_escape`` ± ``D_escape_err`` (length^2/time), extrapolated in 1/L, with the fit's
        chi^2 and the per-width escape rates.
    """
    n = 4 if widths is None else len(widths)
    with _Bar(progress, _total(_count("particles_per_width", particles_per_width)) * n, "part") as cb:
        text = _native.escape(
            _exact("w", w),
            None if widths is None else [float(x) for x in widths],
            _count("particles_per_width", particles_per_width),
            _count("seed", seed),
            _threads(threads),
            _path(checkpoint),
            float(checkpoint_every),
            cb,
        )
    return EscapeResult(text)


def lyapunov(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    collisions_per_batch: Count = 2e6,
    batches: Count = 16,
    starts: Optional[Count] = None,
    seed: Count = 1,
    threads: Optional[Count] = None,
    progress: Progress = None,
    field: Optional[Exact] = None,
) -> LyapunovResult:
    """The largest Lyapunov exponent (``lorentz lyapunov``).

    Parameters
    ----------
    w : gap of the triangular scene (0 < w < 0.3094...); or ``scene="square"`` with ``radius``
        (0 < radius < 1/2), exact as in :func:`diffusion`.
    collisions_per_batch : int
        Collisions of each tangent-space orbit, after a transient.
    batches : int
        Independent orbits, at least 2; the error bar is over them.
    starts : int
        Initial conditions of the divergence measurement from a 4096-bit reference: 0 (none) or
        2 to 10000 (about a second each); default 8, none in a field.
    seed, threads, progress
        As in :func:`diffusion`.
    field : exact number, optional
        A magnetic field B (1/time; 1e-3 <= abs(B) <= 1e3, triangular scene): the tangent dynamics
        of arcs on orbits started in the diffusing part of phase space; 0 or None: no field.

    Returns
    -------
    LyapunovResult
        ``tangent`` (``per_collision`` and ``per_time`` with errors: 1/collision, 1/time) and
        ``divergence`` (one row per horizon); in a field ``field``, ``cyclotron_radius``,
        ``localized_fraction_exact`` and ``rejected_starts`` instead of ``divergence``.
    """
    if starts is None:
        try:
            no_field = field is None or fractions.Fraction(_exact("field", field)) == 0
        except ValueError:
            no_field = False  # not a number: the native call names the field's valid range
        starts = 8 if no_field else 0
    with _Bar(progress, 0, "coll") as cb:
        text = _native.lyapunov(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            _count("collisions_per_batch", collisions_per_batch),
            _count("batches", batches),
            _count("starts", starts),
            _count("seed", seed),
            _threads(threads),
            _optional_exact("field", field),
            cb,
        )
    return LyapunovResult(text)


def superdiffusion(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    collisions: Count = 2e8,
    batches: Count = 32,
    octaves: Count = 12,
    points_per_octave: Count = 4,
    tail_fit_from: float = 8,
    vacf_fit: Optional[Tuple[float, float]] = None,
    msd_fit: Optional[Tuple[float, float]] = None,
    seed: Count = 1,
    threads: Optional[Count] = None,
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60,
    progress: Progress = None,
) -> SuperdiffusionResult:
    """Superdiffusion beyond a finite horizon (``lorentz superdiffusion``): the free-flight
    tails, t·C_xx(t), ⟨Δx²⟩/t against ln t and the limit law of Δx/√(t ln t), each against
    the exact corridor constants.

    Parameters
    ----------
    w : gap of the triangular scene beyond w_inf = 4/√3 − 2 = 0.3094...; or ``scene="square"``
        with ``radius`` (0 < radius < 1/2), exact as in :func:`diffusion`.
    collisions : int
        Collisions in all, shared between the batches (at least 4·2^octaves per batch).
    batches : int
        Independent trajectories, at least 16; the errors are over them.
    octaves : int
        The longest lag is 2^octaves mean free times ℓ (1 to 20).
    points_per_octave : int
        Lags per octave (1 to 16).
    tail_fit_from : float
        The tail fits C + B/s use the times s from this many mean free times on (only those at
        which every batch saw 100 longer flights).
    vacf_fit, msd_fit : (float, float) or None
        The lags, in mean free times, of the plateau of t·C_xx(t) and of the fit
        ⟨Δx²⟩/t = a ln t + b. ``None`` (the default): placed as at 12 octaves relative to the
        longest lag, [2^(octaves−6), 2^(octaves−4)] and [2^(octaves−3), 2^octaves]
        ((64, 256) and (512, 4096) at 12 octaves).
    seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`diffusion` (a checkpoint keeps finished batches and, every
        ``checkpoint_every`` seconds, each trajectory in flight with its observers).

    Returns
    -------
    SuperdiffusionResult
        The exact constants, the measured ones with errors, and the ``lags`` and ``limit_law``
        tables as numpy structured arrays (times in units of length at speed 1).
    """
    with _Bar(progress, _total(_count("collisions", collisions)), "coll") as cb:
        text = _native.superdiffusion(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            _count("collisions", collisions),
            _count("batches", batches),
            _count("octaves", octaves),
            _count("points_per_octave", points_per_octave),
            float(tail_fit_from),
            None if vacf_fit is None else _window("vacf_fit", vacf_fit),
            None if msd_fit is None else _window("msd_fit", msd_fit),
            _count("seed", seed),
            _threads(threads),
            _path(checkpoint),
            float(checkpoint_every),
            cb,
        )
    return SuperdiffusionResult(text)


def audit(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    collisions: Count = 1e6,
    batches: Count = 4,
    sample: float = 1.0,
    reference_bits: Count = 128,
    seed: Count = 1,
    field: Optional[Exact] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> AuditResult:
    """The shadow audit (``lorentz audit``): f64 events replayed in MPFR.

    Parameters
    ----------
    w, scene, radius
        The scene, as in :func:`lyapunov`.
    collisions : int
        Collisions in all, over every batch.
    batches : int
        Independent trajectories, at least 1.
    sample : float
        Fraction of the events replayed, in (0, 1].
    reference_bits : int
        MPFR precision of the replay, 128 to 65536 bits.
    field : str, Fraction or float, optional
        A uniform magnetic field B (inverse time; the cyclotron radius is 1/abs(B) in units of the
        disk radius), exact like ``w``, 1e-6 <= abs(B) <= 1e6; ``None`` or 0: no field. The
        replayed events are then arcs, judged by the arc kernel's running error bound.
    seed, threads, progress
        As in :func:`diffusion`.

    Returns
    -------
    AuditResult
        ``summary`` (events audited, ``outside`` the error model, ambiguous), the one-step error
        ``quantiles`` (flight time, contact point, velocity).
    """
    with _Bar(progress, _total(_count("collisions", collisions)), "coll") as cb:
        text = _native.audit(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            _count("collisions", collisions),
            _count("batches", batches),
            float(sample),
            _count("reference_bits", reference_bits),
            _count("seed", seed),
            _optional_exact("field", field),
            _threads(threads),
            cb,
        )
    return AuditResult(text)


def shadow(
    w: Exact,
    collisions_per_segment: Count = 1000,
    segments: Count = 8,
    reference_bits: Count = 128,
    seed: Count = 1,
    field: Optional[Exact] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> ShadowResult:
    """True orbits shadowing f64 segments of the triangular gas (``lorentz shadow``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap, 0 < w < 0.3094...
    collisions_per_segment : int
        Collisions of each f64 segment.
    segments : int
        Segments, from independent equilibrium starts.
    reference_bits : int
        MPFR precision of the Newton iteration, 128 bits or more.
    field : str, Fraction or float, optional
        A uniform magnetic field B (inverse time; the cyclotron radius is 1/abs(B) in units of the
        disk radius), exact like ``w``, 1e-3 <= abs(B) <= 1e3; ``None`` or 0: no field. The
        segments are f64 orbits on arcs from the diffusing starts of :func:`diffusion` in the
        same field, and their shadows true orbits on arcs.
    seed, threads, progress
        As in :func:`diffusion`.

    Returns
    -------
    ShadowResult
        Per segment: converged, certified (Kantorovich), the distance ``delta`` between the f64
        segment and the true orbit.
    """
    with _Bar(progress, 0, "coll") as cb:
        text = _native.shadow(
            _exact("w", w),
            _count("collisions_per_segment", collisions_per_segment),
            _count("segments", segments),
            _count("reference_bits", reference_bits),
            _count("seed", seed),
            _optional_exact("field", field),
            _threads(threads),
            cb,
        )
    return ShadowResult(text)


def certify(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    collisions: Count = 1000,
    digits: Count = 30,
    seed: Count = 1,
    progress: Progress = None,
) -> CertifyResult:
    """A trajectory segment certified to its digits (``lorentz certify``).

    Parameters
    ----------
    w, scene, radius
        The scene, as in :func:`lyapunov`.
    collisions : int
        Collisions in the segment, from the equilibrium start of batch 0 of
        ``diffusion(seed=seed)``.
    digits : int
        Digits to certify (1 or more).
    seed : int
        Seed of the start.

    Returns
    -------
    CertifyResult
        ``digits_agreed`` (runs at P and 2P bits agree to that many digits), ``bits``, and how
        long the f64 orbit stays within 1e-3 of it (``f64_faithful_collisions``).
    """
    with _Bar(progress, 3 * _total(_count("collisions", collisions)), "coll") as cb:
        text = _native.certify(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            _count("collisions", collisions),
            _count("digits", digits),
            _count("seed", seed),
            cb,
        )
    return CertifyResult(text)


def trajectory(
    start: Tuple[Exact, Exact],
    direction: Tuple[Exact, Exact],
    time: Exact,
    *,
    w: Optional[Exact] = None,
    scene: Optional[str] = None,
    radius: Optional[Exact] = None,
    digits: Count = 30,
    events: bool = False,
    progress: Progress = None,
    field: Optional[Exact] = None,
) -> TrajectoryResult:
    """One trajectory from exact initial conditions to certified digits (``lorentz
    trajectory``): ``start`` (x, y) in world coordinates outside every disk, ``direction``
    (dx, dy) nonzero, total ``time`` > 0, all exact. ``scene`` defaults to "triangular" with
    ``w`` and "square" with ``radius``. ``field`` (exact, 1/time) is a uniform magnetic field
    B: flights are arcs turning counter-clockwise for B > 0 on circles of radius 1/abs(B)
    (0 or None: straight; otherwise 1e-6 <= abs(B) <= 1e6). The result's ``x``, ``y`` and
    ``distance`` are decimal strings carrying exactly the certified digits (1 to 10000)."""
    if scene is None:
        scene = "square" if radius is not None and w is None else "triangular"
    with _Bar(progress, 0, "coll") as cb:
        text = _native.trajectory(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            (_exact("start", start[0]), _exact("start", start[1])),
            (_exact("direction", direction[0]), _exact("direction", direction[1])),
            _exact("time", time),
            _count("digits", digits),
            bool(events),
            _optional_exact("field", field),
            cb,
        )
    return TrajectoryResult(text)


def _many(v: Any) -> bool:
    """Whether ``v`` is several values (a list, tuple or array), not one (text, a number)."""
    return isinstance(v, (list, tuple, np.ndarray))


def bench(
    w: Exact = "0.1",
    collisions_per_thread: Count = 2e7,
    repetitions: Count = 7,
    precision: Union[str, int] = "f64",
    engine: str = "auto",
    observe: str = "none",
    seed: Count = 1,
    threads: Count = 1,
    field: Optional[Exact] = None,
    straight_beside: bool = False,
    progress: Progress = None,
) -> BenchResult:
    """The engine's speed on this machine (``lorentz bench``): ``repetitions`` runs of
    ``collisions_per_thread`` collisions on each of ``threads`` threads, timed, the median
    reported — what a run's time can be planned from
    (:meth:`DiffusionResult.seconds_for`).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap between neighbouring disks (radius 1), w > 0.
    collisions_per_thread : int
        Collisions of each thread in each repetition (the SIMD engine shares them over its 16
        trajectories).
    repetitions : int
        Timed repetitions, 1 to 1000; the median is reported.
    precision : "f64" or int
        The number type: f64, or MPFR with this many bits (53 or more).
    engine : {"auto", "scalar", "simd"}
        The engine timed.
    observe : {"none", "counters", "msd", "diffusion", "hops"}
        Observers run beside the engine: none (the bare engine), or those of an analysis
        (``"diffusion"``: the counters and MSD of ``diffusion``).
    seed : int
        Seed of the equilibrium starts.
    threads : int
        Threads timed at once, one trajectory (or SIMD block) each, 1 to 4 per core; default 1,
        the speed of one core.
    field : str, float, Fraction or Decimal, optional
        A magnetic field B (like ``diffusion``'s): time the f64 arc kernel, bare.
    straight_beside : bool
        With ``field``: time straight flights too, each repetition right after the arcs'.
    progress : bool, callable or None
        As in :func:`diffusion`, over repetitions.

    Returns
    -------
    BenchResult
        ``collisions_per_second`` (all threads) and ``collisions_per_second_per_thread``
        (collisions/s), ``ns_per_collision`` (ns per collision per thread), ``samples`` (each
        repetition's collisions/s), ``divider_bound`` (SIMD engine), ``meta``.

    Timings depend on the machine and on what else runs on it: compare runs made side by side.
    """
    with _Bar(progress, _total(_count("repetitions", repetitions)), "rep") as cb:
        text = _native.bench(
            _exact("w", w),
            _count("collisions_per_thread", collisions_per_thread),
            _count("repetitions", repetitions),
            str(precision),
            str(engine),
            str(observe),
            _count("seed", seed),
            _count("threads", threads),
            None if field is None else _exact("field", field),
            bool(straight_beside),
            cb,
        )
    return BenchResult(text)


def constants(
    w: Any = None, precision: Union[str, int] = "f64", *, radius: Any = None
) -> Union[ConstantsResult, ConstantsTable]:
    """Every closed form of a scene (``lorentz constants --json``) at the working ``precision``.

    ``w``: the triangular gas at gap w > 0 — lattice spacing, density, w_inf, w_0, trap area,
    Santaló's mean free path, hop time, D_MZ, D_Bo, the bound on free paths; or ``radius``:
    the square lattice (0 < radius < 1/2). At an infinite horizon (w >= w_inf, every square
    lattice) ``superdiffusion`` holds the corridors (direction, angle, period, width) and the
    exact constants: ``C_flow`` (P(tau > s) ~ C_flow/s under the flow), ``C_map``
    (mu(tau > s) ~ C_map/s^2 under the billiard map), ``D_sup`` (dx/sqrt(t ln t) -> N(0, D_sup)),
    ``msd_x_t_ln_t`` = 2 D_sup and ``msd_r_t_ln_t`` = 2 C_flow (the coefficients of t ln t in
    <dx^2> and <dr^2>). Values carry every digit of the working precision in ``to_json()``.

    Given several gaps or radii (a list, tuple or numpy array) it returns a
    :class:`ConstantsTable`: one :class:`ConstantsResult` per value, and each scalar constant as a
    numpy array over them (``lg.constants(np.linspace(0.05, 0.3, 6)).D_MZ``)."""
    if _many(w) or _many(radius):
        if w is not None and radius is not None:
            raise ValueError("give w (the triangular gas) or radius (the square lattice), not both")
        values = w if w is not None else radius
        key = "w" if w is not None else "radius"
        return ConstantsTable([constants(**{key: v}, precision=precision) for v in values])
    return ConstantsResult(
        _native.constants(_optional_exact("w", w), _optional_exact("radius", radius), str(precision))
    )


def report(
    path: PathLike,
    out: Optional[PathLike] = None,
    quick: bool = False,
    reference_bits: Count = 128,
    max_rerun_collisions: Optional[Count] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> ReportResult:
    """The publication audit of a result file (``lorentz report``): re-runs its recorded
    configuration, checks every identity and writes report.md, report.html and report.json to
    ``out`` (default: next to the file). The verdict is the result's ``verdict``: PASS, FAIL, or
    INCOMPLETE when a check was skipped (re-runs beyond ``max_rerun_collisions``, by default
    1e12 or 2e9 with ``quick``; too few batches to judge); it is returned, not raised (``raise
    CheckFailedError`` yourself to stop a pipeline)."""
    with _Bar(progress, 0, "coll") as cb:
        text = _native.report(
            os.fspath(path),
            _path(out),
            bool(quick),
            _count("reference_bits", reference_bits),
            None if max_rerun_collisions is None else _count("max_rerun_collisions", max_rerun_collisions),
            _threads(threads),
            cb,
        )
    return ReportResult(text)


_KINDS = np.array(["start", "collision", "crossing"])


def _event_array(cols: Dict[str, Any]) -> np.ndarray:
    out = np.empty(len(cols["t"]), dtype=EVENT_DTYPE)
    for name in EVENT_DTYPE.names:
        out[name] = _KINDS[cols["kind"]] if name == "kind" else cols[name]
    return out


class Trajectory:
    """One trajectory's events, in as many chunks as memory asks for.

    ``Trajectory(w, seed=..., batch=b)`` is the trajectory of batch ``b`` of
    ``diffusion(w, seed=...)`` (with ``field``, of the field run: its start drawn from the
    diffusing orbits; ``scene="square", radius=r`` for the square lattice); ``start`` is its
    first row (``kind`` "start", t = 0) and each ``events(n)`` the next ``n`` events, with the
    same bits as one call for all of them (the state and the running time are kept between
    calls). ``time`` is the time of the last event so far.

    >>> tr = Trajectory(w="0.1", seed=3)
    >>> a, b = tr.events(1000), tr.events(1000)
    >>> whole = Trajectory(w="0.1", seed=3).events(2000)
    >>> bool((np.concatenate([a, b]) == whole).all())
    True
    """

    def __init__(
        self,
        w: Optional[Exact] = None,
        *,
        seed: Count = 1,
        batch: Count = 0,
        scene: str = "triangular",
        radius: Optional[Exact] = None,
        field: Optional[Exact] = None,
    ):
        self._stream = _native.EventStream(
            scene,
            _optional_exact("w", w),
            _optional_exact("radius", radius),
            _count("seed", seed),
            _count("batch", batch),
            _optional_exact("field", field),
        )

    @property
    def start(self) -> np.ndarray:
        """The start as a one-row array of dtype :data:`EVENT_DTYPE` (t = 0, kind "start")."""
        return _event_array(self._stream.start())

    @property
    def time(self) -> float:
        """The time of the last event so far (0 before any)."""
        return self._stream.time

    def events(self, n: Count = 100_000, progress: Progress = None) -> np.ndarray:
        """The next ``n`` events (dtype :data:`EVENT_DTYPE`). Memory is checked first:
        ``MemoryError`` names the largest n that fits; take the rest in further calls."""
        with _Bar(progress, _total(_count("n", n)), "ev") as cb:
            return _event_array(self._stream.next(_count("n", n), cb))

    def __repr__(self) -> str:
        return f"<Trajectory at t = {self.time}>"


def events(
    w: Optional[Exact] = None,
    n: Count = 100_000,
    *,
    seed: Count = 1,
    batch: Count = 0,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    field: Optional[Exact] = None,
    progress: Progress = None,
) -> np.ndarray:
    """One trajectory's start and its next ``n`` events, for your own observables.

    A numpy structured array of dtype :data:`EVENT_DTYPE` with ``n + 1`` rows: the start (row 0,
    ``kind`` "start", t = 0) and ``n`` consecutive events, each with ``t`` (time since the start),
    ``x``, ``y`` (unwrapped world position after the event), ``vx``, ``vy`` (velocity after it),
    ``kind`` ("collision" with a disk or "crossing" of a cell edge; ``collision`` the same as a
    bool), ``obstacle`` (the disk or edge label), ``i``, ``j``, ``down`` (the cell). The
    trajectory is batch ``batch`` of ``diffusion(w, seed=seed)`` (the same start), on the f64
    engine. With ``field`` (the magnetic field B, an exact decimal or fraction,
    1e-3 <= abs(B) <= 1e3; triangular lattice) the flights are arcs of radius 1/abs(B),
    counter-clockwise for B > 0, and the trajectory is batch ``batch`` of
    ``diffusion(w, field=B, seed=seed)`` (its start drawn from the diffusing orbits); ``t`` is
    then the arc time and ``x``, ``y`` the event points; ``field=0`` is the run without a field.
    Memory is checked first: ``MemoryError`` names the largest n that fits; for more, continue
    one :class:`Trajectory` in chunks (the same bits)."""
    tr = Trajectory(w, seed=seed, batch=batch, scene=scene, radius=radius, field=field)
    return np.concatenate([tr.start, tr.events(n, progress)])


def _naming_the_close_match(f: Callable[..., Any]) -> Callable[..., Any]:
    """``f`` refusing an unknown keyword with the ``TypeError`` Python raises, naming the
    keyword ``f`` takes that is closest to it (``colisions=`` → ``collisions``)."""
    sig = inspect.signature(f)
    names = list(sig.parameters)

    @functools.wraps(f)
    def checked(*args: Any, **kwargs: Any) -> Any:
        for k in kwargs:
            if k not in sig.parameters:
                close = difflib.get_close_matches(k, names, n=1)
                hint = (
                    f": did you mean {close[0]!r}?"
                    if close
                    else f"; it takes {', '.join(names)}"
                )
                raise TypeError(f"{f.__name__}() got an unexpected keyword argument {k!r}{hint}")
        return f(*args, **kwargs)

    return checked


# Every analysis of the package names the keyword meant when one is misspelt.
for _name in __all__:
    _f = globals().get(_name)
    if inspect.isfunction(_f) and _f.__module__ == __name__:
        globals()[_name] = _naming_the_close_match(_f)
del _name, _f

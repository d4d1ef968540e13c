"""The transport analyses: the diffusion coefficient (or tensor, in a field) and its sweeps,
trap hopping and the hierarchy built on it, backscattering, escape rates and superdiffusion."""

from __future__ import annotations

import json
import os
from typing import Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._inputs import (
    Count,
    Exact,
    PathLike,
    Progress,
    _count,
    _counts,
    _exact,
    _numbers,
    Table,
    _optional_exact,
    _where,
    _path,
    _threads,
    _total,
    _window,
    _table_numbers,
)
from ._current import CurrentResult
from ._cycles import SurvivalResult
from ._keywords import public
from ._progress import _run
from ._results import (
    TableDiffusionResult,
    BackscatterResult,
    DiffusionResult,
    EscapeResult,
    FieldResult,
    HopsResult,
    LatticeWalkResult,
    SuperdiffusionResult,
    TheoryResult,
)


@public
def diffusion(
    w: Optional[Exact] = None,
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
    plan_only: bool = False,
    msd_grid: Union[str, Sequence[float], np.ndarray] = "fit",
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    electric: Optional[Exact] = None,
    electric_angle: Exact = 0,
) -> Union[DiffusionResult, FieldResult, TableDiffusionResult, CurrentResult]:
    """The diffusion coefficient D(w) by the Einstein formula (``lorentz diffusion``), with a
    magnetic ``field`` the diffusion tensor (``lorentz diffusion --field``), or under a
    thermostatted ``electric`` field the current (``lorentz diffusion --electric``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap between neighbouring disks (radius 1) of the triangular scene: 0 < w < w_inf =
        4/sqrt(3) - 2 = 0.3094... (a finite horizon, where D exists); with a ``field`` any w > 0.
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
        run without a field (its own bits). A field run takes no checkpoint or audit; at
        f64 its trajectories fly on the SIMD arc engine (``engine="auto"``), with the scalar
        kernel's bits.
    localization_samples : int
        With ``field``: phase points classified for the sampled share of localized orbits.
    progress : bool, callable or None
        Show a tqdm bar (if tqdm is installed), or call ``progress(n)`` with collisions done.
        ``None`` (the default): a bar in a Jupyter notebook, none in scripts; ``False``: none.
        With ``rel_err`` the bar counts the pilot, then starts again over the planned run's
        collisions (its time estimate is the planned run's, at its measured speed); a callable
        with a ``restart(total)`` method is told so.
    rel_err : float, optional
        Stop at this relative error of D (``1e-4`` is 0.01 %, from 1e-7 to 0.5): a pilot of
        ``collisions`` measures how the error falls with the collisions, then the run of the
        size it plans runs (the bits of a plain run of that size, resumable with
        ``checkpoint``); ``pilot`` in the result records the pilot. The error reached scatters
        by about 13 % about the target with 32 batches (the pilot's error is itself estimated).
        The planned run continues the pilot's trajectories rather than computing them again,
        and a resumed planned run takes its pilot from its checkpoint.
    plan_only : bool
        With ``rel_err``: run the pilot only and return its result, with ``pilot`` and ``plan``
        (the collisions the target needs, ``plan["collisions"]``, and the seconds they take at
        the pilot's speed, ``plan["seconds"]``), without the planned run. Takes no
        ``checkpoint`` or ``audit``.
    msd_grid : {"fit", "log"}, "log:FROM,TO,PER_OCTAVE" or array of times
        Where the MSD is kept: ``"fit"``, the fit windows' lags (which D is fitted from);
        ``"log"``, also a logarithmic grid from an eighth of the mean free time on (four times
        per octave), with the velocity autocorrelation and its running Green-Kubo integral:
        ``msd_curve`` (a table: ``times``, ``msd``, ``vacf``, ``green_kubo``, each with
        ``_err``) and ``D_green_kubo`` ± ``D_green_kubo_err`` in the result. D keeps its bits;
        the run is about 20 times slower per collision. Your own times (time units, not τ):
        an array such as ``np.array([0, 0.5, 1, 2, 4])`` (from 0 on, increasing, finite, at
        most 1000 of them, the longest at most a hundredth of a batch's trajectory) or
        ``"log:FROM,TO,PER_OCTAVE"`` (t = 0, then FROM·2^(k/PER_OCTAVE) up to TO); the table
        then starts at t = 0 (``msd`` 0 exactly, ``vacf`` 1) and has ``vacf_x`` and ``vacf_y``,
        ⟨v_x(0)v_x(t)⟩ and ⟨v_y(0)v_y(t)⟩ (½ each at t = 0), with ``_err``; the time origins
        are a mean free time apart (further for the longest times), and the run costs about one
        pair sum per time per collision.
    scene : {"triangular", "square"}
        The lattice: ``"triangular"`` (the paper's, needs ``w``) or ``"square"`` (disks of
        ``radius`` at unit spacing). The square scene has corridors, so only a run in a
        ``field`` (which bounds every flight) has a diffusion coefficient there.
    radius : str, float, Fraction or Decimal, optional
        Disk radius of the square scene, 0 < radius < 1/2, taken exactly like ``w``.
    table : dict or path, optional
        Any periodic table of disks instead of ``scene``, ``w`` and ``radius``: a dict
        ``{"lattice": {"e1": [a, 0], "e2": [b, h]}, "disks": [{"centre": [x, y], "radius": r},
        ...]}`` (every number exact like ``w``; ``"name"`` optional) or the path of a TOML table
        file (``examples/tables/``). Refused with ``ValueError`` naming the disks that overlap or
        the open corridor where the analysis needs a finite horizon.
    electric : str, float, Fraction or Decimal, optional, keyword only
        A Gaussian-thermostatted electric field E in the plane (1/time at speed 1: dv/dt = E -
        (E.v)v keeps the speed 1), taken exactly like ``w``, 0 < abs(E) <= 10: the run measures
        the current, the mobility J/E (which tends to D as E -> 0), the entropy production E.J and
        the diffusion tensor about the drift. ``None`` or 0: the run without a field (its own
        bits). A finite horizon is needed; the run takes no checkpoint, audit or ``rel_err`` yet
        and runs on the scalar engine.
    electric_angle : str, float, Fraction or Decimal, keyword only
        The field's direction from the x axis in degrees, taken exactly (-360 to 360).

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
    CurrentResult
        With a nonzero ``electric``: ``J_x``, ``J_y``, ``J_parallel``, ``J_perp``,
        ``mobility``, ``entropy_production`` (each with ``_err``), the tensor about the drift
        ``diffusion``, the velocity angle's ``angle_density``.
    """
    if plan_only and rel_err is None:
        raise ValueError("plan_only=True plans a run for a relative error: give rel_err too")
    # A planned run's bar counts its pilot, then starts again over the planned collisions.
    default = 2e8 if rel_err is not None else 2e9
    size = _total(_count("collisions", default if collisions is None else collisions))
    stage = "pilot" if rel_err is not None else ""
    text = _run(_native.diffusion, progress, size, "coll", {
        **_where(scene, table, w, radius),
        "collisions": None if collisions is None else _count("collisions", collisions),
        **_counts(
            batches=batches,
            seed=seed,
            reference_bits=reference_bits,
            localization_samples=localization_samples,
        ),
        "threads": _threads(threads),
        "engine": str(engine),
        "precision": str(precision),
        "window": (float(window[0]), float(window[1])),
        "check_window": (float(check_window[0]), float(check_window[1])),
        "checkpoint": _path(checkpoint),
        "checkpoint_every": float(checkpoint_every),
        "audit": None if audit is None else float(audit),
        "field": _optional_exact("field", field),
        "electric": _optional_exact("electric", electric),
        "electric_angle": _exact("electric_angle", electric_angle),
        "rel_err": None if rel_err is None else float(rel_err),
        "plan_only": bool(plan_only),
        "msd_grid": _numbers("msd_grid", msd_grid),
    }, stage)
    if '"J_parallel"' in text:
        return CurrentResult(text)
    if '"D_xy"' in text:
        return FieldResult(text)
    if '"identities"' in text:
        return TableDiffusionResult(text)
    return DiffusionResult(text)


@public
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
    return HopsResult(_hop_analysis(_native.hops, w, collisions, batches, order, seed, threads,
                                    checkpoint, checkpoint_every, progress, engine=str(engine)))


@public
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


@public
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
                  checkpoint_every, progress, **more: str) -> str:
    """The JSON of the hop analysis ``native`` (hops, theory, lattice-walk): the parameters they
    share, then ``more`` (hops' ``engine``)."""
    params = {
        "w": _exact("w", w),
        **_counts(collisions=collisions, batches=batches, order=order, seed=seed),
        "threads": _threads(threads),
        "checkpoint": _path(checkpoint),
        "checkpoint_every": float(checkpoint_every),
        **more,
    }
    return _run(native, progress, _total(_count("collisions", collisions)), "coll", params)


@public
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
    text = _run(_native.backscatter, progress, _total(_count("particles", particles)), "inj", {
        "w": _exact("w", w),
        **_counts(particles=particles, batches=batches, seed=seed),
        "threads": _threads(threads),
        "precision": str(precision),
    })
    return BackscatterResult(text)


@public
def escape(
    w: Optional[Exact] = None,
    widths: Optional[Sequence[float]] = None,
    particles_per_width: Count = 2e5,
    seed: Count = 1,
    threads: Optional[Count] = None,
    checkpoint: Optional[PathLike] = None,
    checkpoint_every: float = 60.0,
    progress: Progress = None,
    *,
    repeller: bool = False,
    side: Exact = 6,
    radius: Exact = 1,
    open_table: Optional[Union[dict, PathLike]] = None,
    particles: Count = 1e7,
    window: Count = 3,
) -> Union[EscapeResult, SurvivalResult]:
    """Escape rates (``lorentz escape``): D from the escape out of open strips of the triangular
    gas (Gaspard–Baras, ``w=``), or an open table's escape rate by survival (``repeller=True``
    or ``open_table=``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap of the strips' triangular gas, 0 < w < w_inf = 0.3094... (not with an open table).
    widths : sequence of float, optional
        At least 3 distinct strip widths L (lengths; default 8a, 12a, 16a, 24a with a = 2 + w),
        each at least max(4a, 10 mean free paths) and at most 2000.
    particles_per_width : int
        Particles injected into each strip, split into the batches the error bars are over.
    seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`diffusion` (an open table keeps no checkpoint).
    repeller : bool
        The open table is the three-disk repeller: disks of radius ``radius`` = a at the corners
        of the equilateral triangle of side ``side`` = R (lengths, exact as typed: R > 2a).
    side, radius : exact number
        R and a of the repeller (defaults 6 and 1).
    open_table : dict or path, optional
        An open table given as data: ``{"name": ..., "disks": [{"centre": [x, y], "radius":
        r}, ...]}`` (2 to 64 disjoint disks, numbers exact as strings, Fractions or ints), or
        the path of such a JSON file.
    particles : int
        Particles started on the open table (32000 to 1e12), split into 32 batches.
    window : int
        The collision n0 at which the survival window starts (1 to 20); the next window is the
        check.

    Returns
    -------
    EscapeResult
        Strips: ``D_escape`` ± ``D_escape_err`` (length^2/time), extrapolated in 1/L, with the
        fit's chi^2 and the per-width escape rates.
    SurvivalResult
        An open table: ``gamma`` (1/time), ``lyapunov`` (1/time), ``entropy`` (h_KS, 1/time),
        each with ``_err``, and the estimates of every window start as arrays.
    """
    if repeller or open_table is not None:
        if repeller and open_table is not None:
            raise ValueError("repeller=True and open_table= name two tables: give one")
        if w is not None or widths is not None or checkpoint is not None:
            raise ValueError("an open table takes no w=, widths= or checkpoint=: leave them out")
        text = _run(_native.survival, progress, _total(_count("particles", particles)), "part", {
            "side": _exact("side", side),
            "radius": _exact("radius", radius),
            "open_table": None if open_table is None else _open_table_json(open_table),
            **_counts(particles=particles, window=window, seed=seed),
            "threads": _threads(threads),
        })
        return SurvivalResult(text)
    if w is None:
        raise ValueError("w= is missing: give the gap (0 < w < w_inf = 0.3094...), or repeller=True or open_table=")
    n = 4 if widths is None else len(widths)
    total = _total(_count("particles_per_width", particles_per_width)) * n
    text = _run(_native.escape, progress, total, "part", {
        "w": _exact("w", w),
        "widths": None if widths is None else [float(x) for x in widths],
        **_counts(particles_per_width=particles_per_width, seed=seed),
        "threads": _threads(threads),
        "checkpoint": _path(checkpoint),
        "checkpoint_every": float(checkpoint_every),
    })
    return EscapeResult(text)


def _open_table_json(table: Union[dict, PathLike]) -> str:
    """An open table (a dict, or the path of a JSON file) as its JSON, numbers as exact text."""
    if isinstance(table, dict):
        return json.dumps(_table_numbers(table))
    if isinstance(table, (str, os.PathLike)):
        with open(os.fspath(table), encoding="utf-8") as f:
            return f.read()
    raise TypeError(f"open_table must be a dict or the path of a JSON file, not {type(table).__name__}")


@public
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
    flights: str = "auto",
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
    flights : {"auto", "walk", "jump"}
        How flights cross the lattice, as in :func:`lyapunov`: ``"auto"`` jumps the long flights
        of the square scene (2**-32 <= radius <= 1/8) and of the triangular one (w >= 6), where
        jumps are faster, to the cell of the first disk they can meet; ``"walk"`` crosses cell by
        cell. Recorded as ``flights``.
    seed, threads, checkpoint, checkpoint_every, progress
        As in :func:`diffusion` (a checkpoint keeps finished batches and, every
        ``checkpoint_every`` seconds, each trajectory in flight with its observers).

    Returns
    -------
    SuperdiffusionResult
        The exact constants, the measured ones with errors, and the ``lags`` and ``limit_law``
        tables as numpy structured arrays (times in units of length at speed 1).
    """
    total = _total(_count("collisions", collisions))
    text = _run(_native.superdiffusion, progress, total, "coll", {
        "scene": scene,
        "w": _optional_exact("w", w),
        "radius": _optional_exact("radius", radius),
        **_counts(
            collisions=collisions,
            batches=batches,
            octaves=octaves,
            points_per_octave=points_per_octave,
            seed=seed,
        ),
        "tail_fit_from": float(tail_fit_from),
        "vacf_fit": None if vacf_fit is None else _window("vacf_fit", vacf_fit),
        "msd_fit": None if msd_fit is None else _window("msd_fit", msd_fit),
        "flights": str(flights),
        "threads": _threads(threads),
        "checkpoint": _path(checkpoint),
        "checkpoint_every": float(checkpoint_every),
    })
    return SuperdiffusionResult(text)

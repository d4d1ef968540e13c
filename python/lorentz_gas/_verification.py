"""The analyses of single orbits and of how far the numbers can be trusted: the Lyapunov exponent,
the shadow audit, true shadowing orbits, certified segments and trajectories; with the scene's
closed forms and the publication audit of a result file (the engine's speed: ``_bench``)."""

from __future__ import annotations

import os
import tempfile
from typing import Any, Optional, Sequence, Tuple, Union

import numpy as np

from . import _native
from ._inputs import (
    Count,
    Exact,
    PathLike,
    Progress,
    _count,
    _counts,
    _driving,
    _numbers,
    _exact,
    _many,
    Table,
    _optional_exact,
    _where,
    _path,
    _threads,
    _total,
)
from ._keywords import public
from ._progress import _run
from ._results import (
    AuditResult,
    CertifyResult,
    ConstantsResult,
    FreePathResult,
    ConstantsTable,
    LyapunovResult,
    ReportResult,
    Result,
    ShadowResult,
    TrajectoryResult,
)


@public
def lyapunov(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    collisions_per_batch: Count = 2e6,
    batches: Count = 16,
    starts: Optional[Count] = None,
    seed: Count = 1,
    threads: Optional[Count] = None,
    progress: Progress = None,
    field: Optional[Exact] = None,
    flights: str = "auto",
    electric: Optional[Exact] = None,
    electric_angle: Optional[Exact] = None,
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
        2 to 10000 (about a second each); default 8, none in a field nor where long flights
        jump (it replays the cell walk at up to 4096 bits).
    seed, threads, progress
        As in :func:`diffusion`.
    field : exact number, optional
        A magnetic field B (1/time; 1e-3 <= abs(B) <= 1e3, either scene): the tangent dynamics
        of arcs on orbits started in the diffusing part of phase space; 0 or None: no field.
    flights : {"auto", "walk", "jump"}
        How straight flights cross the lattice: ``"jump"`` straight to the cell of the first disk
        they can meet (the square scene with 2**-32 <= radius <= 1/4, the triangular one with
        w_inf < w <= 2**20 - 2; a collision then costs the same whatever the flight's length),
        ``"walk"`` cell by cell (the reference), ``"auto"`` jump with 2**-32 <= radius <= 1/8 and
        w >= 6, where jumps are faster. Recorded as ``tangent["flights"]``.
    table : dict or path, optional
        Any periodic table of disks instead of ``scene``, ``w`` and ``radius``, as in
        :func:`diffusion`.
    electric : str, Fraction or float, optional
        A Gaussian-thermostatted electric field E in the plane (1/time at speed 1: dv/dt = E -
        (E.v)v), exact, 0 < abs(E) <= 10: the Lyapunov pair of the driven gas (each trajectory
        warmed up for max(1000, collisions_per_batch/64) collisions first); 0 or None: no
        field. Not with ``field``; ``starts`` must be 0 or None.
    electric_angle : str, Fraction or float, optional
        With ``electric``: the field's angle from the x axis in degrees, exact; ``None``: 0.

    Returns
    -------
    LyapunovResult
        ``tangent`` (``per_collision`` and ``per_time`` with errors: 1/collision, 1/time) and
        ``divergence`` (one row per horizon); in a field ``field``, ``cyclotron_radius``,
        ``localized_fraction_exact`` and ``rejected_starts`` instead of ``divergence``; under
        ``electric``, ``lambda_plus`` and ``lambda_minus`` (1/time) with errors,
        ``contraction`` (⟨α⟩ = E·J, 1/time), ``sum_rule`` (λ₊ + λ₋ against −⟨α⟩, paired
        Student-t: ``difference``, ``err``, ``dof``, ``z``, ``bound``), ``sum_rule_residual``
        beside ``sum_rule_residual_bound`` (per trajectory) and ``kaplan_yorke`` (dimensionless)
        instead of ``divergence``.
    """
    text = _run(_native.lyapunov, progress, 0, "coll", {
        **_where(scene, table, w, radius),
        **_counts(collisions_per_batch=collisions_per_batch, batches=batches, seed=seed),
        "starts": None if starts is None else _count("starts", starts),
        "threads": _threads(threads),
        "flights": flights,
        **_driving(field, electric, electric_angle),
    })
    return LyapunovResult(text)


@public
def free_paths(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    collisions: Count = 1.6e7,
    batches: Count = 16,
    seed: Count = 1,
    flights: str = "auto",
    bins: Optional[Union[Sequence[float], np.ndarray]] = None,
    keep_samples: Count = 0,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> FreePathResult:
    """The free path between collisions against its Boltzmann–Grad limit law
    (``lorentz free-paths``): the histogram of ξ = τ/ℓ (τ the flight from one collision to the
    next, ℓ Santaló's mean free path), ⟨ξ⟩ (exactly 1) and ⟨ln ξ⟩, against the law of r → 0
    that every lattice of small disks approaches.

    Parameters
    ----------
    w : gap of the triangular scene (w > 0); or ``scene="square"`` with ``radius``
        (0 < radius < 1/2; small radii are the limit's regime), exact as in :func:`diffusion`.
    collisions : int
        Collisions in all, shared between the batches (at least 1001 per batch; each batch's
        first, partial flight is not counted).
    batches : int
        Independent trajectories, at least 2; the errors are over them.
    flights : {"auto", "walk", "jump"}
        How flights cross the lattice, as in :func:`lyapunov`. Recorded as ``flights``.
    bins : array of float, optional
        Your bin edges in ξ = τ/ℓ (dimensionless), such as ``np.linspace(0, 4, 17)``: 2 to
        1001 finite numbers >= 0, increasing; a flight outside ``[bins[0], bins[-1])`` falls in
        no bin (the probabilities stay shares of all flights). Default: quarters up to 2, then
        wider bins to an open last one.
    keep_samples : int
        Keep the ξ of this many flights (0 to 1e6, at most the complete flights) as
        ``free_path_samples``: each batch keeps its share, every k-th complete flight from its
        first, so that they spread over the whole trajectory and are nearly independent.
    seed, threads, progress
        As in :func:`diffusion`.
    table : dict or path, optional
        Any periodic table of disks instead of ``scene``, ``w`` and ``radius``, as in
        :func:`diffusion`.

    Returns
    -------
    FreePathResult
        ``mean``, ``ln_mean`` with errors and limits, the ``bins`` table (probabilities of
        ξ, dimensionless, against the limit law, with z-scores) and ``free_path_samples`` (an
        array of ξ; empty unless ``keep_samples``). ``r.plot()`` draws the histogram against
        the limit law (matplotlib).
    """
    text = _run(_native.free_paths, progress, _total(_count("collisions", collisions)), "coll", {
        **_where(scene, table, w, radius),
        **_counts(collisions=collisions, batches=batches, seed=seed),
        "flights": str(flights),
        "bins": None if bins is None else _numbers("bins", bins),
        "keep_samples": _count("keep_samples", keep_samples),
        "threads": _threads(threads),
    })
    return FreePathResult(text)


@public
def audit(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    collisions: Count = 1e6,
    batches: Count = 4,
    sample: float = 1.0,
    reference_bits: Count = 128,
    seed: Count = 1,
    field: Optional[Exact] = None,
    electric: Optional[Exact] = None,
    electric_angle: Optional[Exact] = None,
    flights: str = "auto",
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
    electric : str, Fraction or float, optional
        A Gaussian-thermostatted electric field E in the plane (1/time at speed 1: dv/dt = E -
        (E.v)v), exact like ``w``, 0 < abs(E) <= 10; ``None`` or 0: no field. Not with ``field``.
        The replayed events are then thermostatted flights, judged by their kernel's running
        error bound and checked against independent closed forms
        (``summary["worst"][i]["check"]["flight_identity"]``, at most 1).
    electric_angle : str, Fraction or float, optional
        With ``electric``: the field's angle from the x axis in degrees, exact; ``None``: 0.
    flights : {"auto", "walk", "jump"}
        How straight flights cross the lattice, as in :func:`lyapunov`: with ``"jump"`` each long
        flight is replayed as a whole, against the exact column walk on the square lattice
        (``summary["jumps"]``), by the MPFR trap walk on the triangular one
        (``summary["triangular_jumps"]``); ``"walk"`` replays every cell crossing; ``"auto"``
        jumps with 2**-32 <= radius <= 1/8 and w >= 6, where jumps are faster (not in a field).
        Recorded as ``flights``.
    seed, threads, progress
        As in :func:`diffusion`.
    table : dict or path, optional
        Any periodic table of disks instead of ``scene``, ``w`` and ``radius``, as in
        :func:`diffusion`.

    Returns
    -------
    AuditResult
        ``summary`` (events audited, ``outside`` the error model, ambiguous), the one-step error
        ``quantiles`` (flight time, contact point, velocity).
    """
    text = _run(_native.audit, progress, _total(_count("collisions", collisions)), "coll", {
        **_where(scene, table, w, radius),
        **_counts(collisions=collisions, batches=batches, reference_bits=reference_bits, seed=seed),
        "sample": float(sample),
        **_driving(field, electric, electric_angle),
        "flights": str(flights),
        "threads": _threads(threads),
    })
    return AuditResult(text)


@public
def shadow(
    w: Optional[Exact] = None,
    collisions_per_segment: Count = 1000,
    segments: Count = 8,
    reference_bits: Count = 128,
    seed: Count = 1,
    field: Optional[Exact] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    electric: Optional[Exact] = None,
    electric_angle: Optional[Exact] = None,
) -> ShadowResult:
    """True orbits shadowing f64 segments (``lorentz shadow``).

    Parameters
    ----------
    w : str, float, Fraction or Decimal
        Gap of the triangular scene, 0 < w < 0.3094...; or ``scene="square"`` with ``radius``
        (0 < radius < 1/2, exact like ``w``).
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
    electric : str, Fraction or float, optional
        A Gaussian-thermostatted electric field E in the plane (1/time at speed 1: dv/dt = E -
        (E.v)v), exact like ``w``, 0 < abs(E) <= 10; ``None`` or 0: no field (the field-free
        bits). The segments are f64 thermostatted orbits from the equilibrium starts, and their
        shadows true thermostatted orbits. Not with ``field``.
    electric_angle : str, Fraction or float, optional
        With ``electric``: the field's angle from the x axis in degrees, exact; ``None``: 0.
    seed, threads, progress
        As in :func:`diffusion`.
    table : dict or path, optional
        A table given as data, as in :func:`diffusion`: one disk per cell at the lattice points
        (true shadowing is written for a lattice of equal disks); another is refused naming that.

    Returns
    -------
    ShadowResult
        Per segment: converged, certified (Kantorovich), the distance ``delta`` between the f64
        segment and the true orbit.
    """
    text = _run(_native.shadow, progress, 0, "coll", {
        **_where(scene, table, w, radius),
        **_counts(
            collisions_per_segment=collisions_per_segment,
            segments=segments,
            reference_bits=reference_bits,
            seed=seed,
        ),
        **_driving(field, electric, electric_angle),
        "threads": _threads(threads),
    })
    return ShadowResult(text)


@public
def certify(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
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
    table : dict or path, optional
        Any periodic table of disks instead of ``scene``, ``w`` and ``radius``, as in
        :func:`diffusion`.

    Returns
    -------
    CertifyResult
        ``digits_agreed`` (runs at P and 2P bits agree to that many digits), ``bits``, and how
        long the f64 orbit stays within 1e-3 of it (``f64_faithful_collisions``).
    """
    text = _run(_native.certify, progress, 3 * _total(_count("collisions", collisions)), "coll", {
        **_where(scene, table, w, radius),
        **_counts(collisions=collisions, digits=digits, seed=seed),
    })
    return CertifyResult(text)


@public
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
    electric: Optional[Exact] = None,
    electric_angle: Optional[Exact] = None,
) -> TrajectoryResult:
    """One trajectory from exact initial conditions to certified digits (``lorentz
    trajectory``): ``start`` (x, y) in world coordinates outside every disk, ``direction``
    (dx, dy) nonzero, total ``time`` > 0, all exact. ``scene`` defaults to "triangular" with
    ``w`` and "square" with ``radius``. ``field`` (exact, 1/time) is a uniform magnetic field
    B: flights are arcs turning counter-clockwise for B > 0 on circles of radius 1/abs(B)
    (0 or None: straight; otherwise 1e-6 <= abs(B) <= 1e6). ``electric`` (exact, 1/time,
    abs(E) <= 10) is a Gaussian-thermostatted electric field E at ``electric_angle`` degrees
    from the x axis (exact; None: 0): flights of the thermostat's kernel with certified events
    (0 or None: straight; not with ``field``). The result's ``x``, ``y`` and
    ``distance`` are decimal strings carrying exactly the certified digits (1 to 10000)."""
    if scene is None:
        scene = "square" if radius is not None and w is None else "triangular"
    text, printed = _run(_native.trajectory, progress, 0, "coll", {
        "scene": scene,
        "w": _optional_exact("w", w),
        "radius": _optional_exact("radius", radius),
        "start": (_exact("start", start[0]), _exact("start", start[1])),
        "direction": (_exact("direction", direction[0]), _exact("direction", direction[1])),
        "time": _exact("time", time),
        **_counts(digits=digits),
        "events": bool(events),
        **_driving(field, electric, electric_angle),
    })
    return TrajectoryResult(text, printed=printed)


@public
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
    text, printed = _native.constants(
        {"w": _optional_exact("w", w), "radius": _optional_exact("radius", radius),
         "precision": str(precision)}
    )
    return ConstantsResult(text, printed=printed)


@public
def report(
    path: Union[PathLike, Result],
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
    CheckFailedError`` yourself to stop a pipeline).

    ``path`` may be a result itself (``lg.report(lg.diffusion(...))``): its JSON is written to
    ``out``/result.json first (a result.json already there must be this result's, byte for
    byte, else ``ValueError``; without ``out``, a new folder ``lorentz-report-*`` in the
    temporary directory, named on the last line of ``str()`` of the report), and that file is
    audited, so the report names a file that stays beside it."""
    if isinstance(path, Result):
        if out is None:
            out = tempfile.mkdtemp(prefix="lorentz-report-")
        path = _result_file(path, out)
    text, printed = _run(_native.report, progress, 0, "coll", {
        "path": os.fspath(path),
        "out": _path(out),
        "quick": bool(quick),
        **_counts(reference_bits=reference_bits),
        "max_rerun_collisions": None if max_rerun_collisions is None
        else _count("max_rerun_collisions", max_rerun_collisions),
        "threads": _threads(threads),
    })
    return ReportResult(text, printed=printed)


def _result_file(result: Result, out: PathLike) -> str:
    """``out``/result.json holding ``result``'s JSON: created, or found with exactly that text;
    never another file overwritten."""
    folder = os.fspath(out)
    os.makedirs(folder, exist_ok=True)
    try:
        return result.save(os.path.join(folder, "result.json"))
    except ValueError as e:
        raise ValueError(f"{e}; give another out=") from None

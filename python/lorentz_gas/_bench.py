"""The engine's speed (``lorentz bench``): collisions per second per thread, the observers' costs
and the long flights of small scatterers, timed as the command line times them."""

from __future__ import annotations

from typing import Any, Optional, Union

from . import _native
from ._inputs import (Count, Exact, Progress, Table, _count, _counts, _exact, _many,
                      _driving, _table_json, _total)
from ._keywords import public
from ._progress import _run
from ._results import BenchResult


@public
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
    oracle_floor: bool = False,
    long_flights: Optional[Any] = None,
    scene: str = "square",
    collisions_per_radius: Count = 1e6,
    walk_collisions: Count = 1e4,
    progress: Progress = None,
    *,
    table: Optional[Table] = None,
    diffusion_beside: bool = False,
    electric: Optional[Exact] = None,
    electric_angle: Optional[Exact] = None,
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
    oracle_floor : bool
        With ``field`` on the SIMD engine: also time the arc engine fed each event's winner from
        a tape of its own run (only that disk and edge computed, the same bits) beside the full
        engine on the same tape, one thread: the speed no choice of the next event in advance
        can beat with this kernel's arithmetic, on this CPU (``oracle`` in the result). With
        ``electric``: the thermostat's floor, each event of a tape of its walk (the run's
        ``collisions_per_thread``, at most 2e5 collisions) certified given only the candidate
        the full search found, beside the full search on the same tape (``oracle``: ``events``,
        ``collisions``, ``identical``, ``full_ns_per_collision``, ``floor_ns_per_collision``,
        ``floor_collisions_per_second``, ``samples``, ``full_samples``, ``paired_ratio``,
        ``floor_over_straight``: the median of each repetition's floor rate over the straight
        flights' per thread).
    long_flights : list of exact numbers, optional
        Radii of the square scene (each 2**-32 <= r <= 1/4; the first is the reference), or with
        ``scene="triangular"`` gaps w of the triangular one (w_inf < w <= 2**20 - 2): time a
        collision against the length of its flight, long flights jumped, the values in turns on
        one thread, with ``walk_collisions`` of the cell walk beside (``lorentz bench
        --long-flights``). Only ``scene``, ``repetitions``, ``seed``, ``collisions_per_radius``,
        ``walk_collisions`` and ``progress`` apply with it.
    scene : {"square", "triangular"}
        With ``long_flights``: the lattice timed (square by default: its values are radii).
    collisions_per_radius : int
        With ``long_flights``: collisions of each timed run with jumps, per radius (or gap) and
        repetition.
    walk_collisions : int
        With ``long_flights``: collisions of each timed walk cell by cell (0: not timed).
    progress : bool, callable or None
        As in :func:`diffusion`, over repetitions.
    table : dict or path, keyword only
        A periodic table of disks given as data (as in :func:`diffusion`: a dict or the path of a
        TOML table file) timed beside the triangular gas at ``w`` (``lorentz bench --table``):
        each repetition of its straight flights right after the triangular one's, on the same
        threads and engine (its cell on the SIMD lanes), f64 without a ``field`` or observers.
    diffusion_beside : bool, keyword only
        With ``field``: time :func:`diffusion` in the field end to end too (as many collisions,
        the same threads), each repetition right after the arcs' (``diffusion`` in the result).
    electric : str, Fraction or float, keyword only
        Time the walk under a Gaussian-thermostatted electric field E at ``electric_angle``
        (1/time, exact like ``w``, 0 < abs(E) <= 10) beside straight flights, in alternation in one run (``lorentz
        bench --electric``): the thermostat's ``collisions_per_second_per_thread`` and
        ``samples``, the straight ones' ``straight_collisions_per_second_per_thread`` and
        ``straight_samples``, ``thermostat_over_straight`` (the medians' ratio) and
        ``paired_ratio`` (the median of each repetition's ratio). Bare: no ``observe``,
        ``field``, ``table`` or other bench beside it.
    electric_angle : str, Fraction or float, keyword only
        With ``electric``: the field's angle from the x axis in degrees, exact (as
        :func:`diffusion` takes it); None: 0.

    Returns
    -------
    BenchResult
        ``collisions_per_second`` (all threads) and ``collisions_per_second_per_thread``
        (collisions/s), ``ns_per_collision`` (ns per collision per thread), ``samples`` (each
        repetition's collisions/s), ``divider_bound`` (SIMD engine), ``meta``; with
        ``straight_beside``: ``straight``; with ``diffusion_beside``: ``diffusion``, a dict
        (``collisions``, ``batches``, ``samples`` and ``collisions_per_second_per_thread`` in
        collisions/s, ``over_engine``, its median over the engine's, and ``paired_ratio``, the
        median of each repetition's ratio); with ``oracle_floor``: ``oracle``, a dict (``steps``,
        ``collisions`` and ``events`` over the tape, ``full_ns_per_collision`` and
        ``floor_ns_per_collision`` in ns, ``floor_collisions_per_second`` in collisions/s, and
        ``paired_ratio``, the median of floor over full time). With ``table``: ``table``, a dict
        (``table``, the table's name; ``samples`` and ``collisions_per_second_per_thread`` in
        collisions/s; ``over_triangular``, its median over the triangular gas's; ``paired_ratio``,
        the median of each repetition's ratio; ``crossings_per_collision``). With
        ``long_flights``: ``config`` and ``rows``, a numpy structured array with one record per
        radius or gap (``radius`` or ``w``, ``mean_free_path``, ``ns_per_collision``, ``over_first``,
        ``walk_ns_per_collision``, ``walk_over_jump``; NaN where the walk was not timed).

    Timings depend on the machine and on what else runs on it: compare runs made side by side.
    """
    if long_flights is not None:
        return _bench_long_flights(
            scene, long_flights, collisions_per_radius, walk_collisions, repetitions, seed,
            progress,
            unused={"w": w != "0.1", "collisions_per_thread": collisions_per_thread != 2e7,
                    "precision": str(precision) != "f64", "engine": engine != "auto",
                    "observe": observe != "none", "threads": threads != 1,
                    "field": field is not None, "straight_beside": bool(straight_beside),
                    "oracle_floor": bool(oracle_floor), "table": table is not None,
                    "diffusion_beside": bool(diffusion_beside), "electric": electric is not None,
                    "electric_angle": electric_angle is not None},
        )
    if collisions_per_radius != 1e6 or walk_collisions != 1e4 or scene != "square":
        raise ValueError(
            "scene, collisions_per_radius and walk_collisions apply with long_flights= only"
        )
    text = _run(_native.bench, progress, _total(_count("repetitions", repetitions)), "rep", {
        "w": _exact("w", w),
        **_counts(
            collisions_per_thread=collisions_per_thread,
            repetitions=repetitions,
            seed=seed,
            threads=threads,
        ),
        "precision": str(precision),
        "engine": str(engine),
        "observe": str(observe),
        **_driving(field, electric, electric_angle),
        "straight_beside": bool(straight_beside),
        "oracle_floor": bool(oracle_floor),
        "diffusion_beside": bool(diffusion_beside),
        "table": None if table is None else _table_json(table),
    })
    return BenchResult(text)


def _bench_long_flights(scene, values, collisions_per_radius, walk_collisions, repetitions,
                        seed, progress, unused):
    """``bench(long_flights=...)``: refuses the keywords that do not apply, then times."""
    given = [k for k, v in unused.items() if v]
    if given:
        raise ValueError(
            f"{', '.join(given)}: long_flights= times one lattice on one thread; only scene, "
            "repetitions, seed, collisions_per_radius and walk_collisions apply"
        )
    values = [_exact("long_flights", r) for r in (values if _many(values) else [values])]
    total = _total(_count("repetitions", repetitions))
    text = _run(_native.bench_long_flights, progress, total, "rep", {
        "scene": str(scene),
        "long_flights": values,
        **_counts(
            collisions_per_radius=collisions_per_radius,
            walk_collisions=walk_collisions,
            repetitions=repetitions,
            seed=seed,
        ),
    })
    return BenchResult(text)

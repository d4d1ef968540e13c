"""Sweeps: D(w) over a grid of gaps, the diffusion tensor in a field over gaps and fields, or the
driven gas over fields E; in
parts (``shard=``, merged by :func:`merge`, as ``lorentz sweep --shard`` and ``lorentz merge``),
or spread over a process pool or a cluster (``executor=``) with the bits of one process."""

from __future__ import annotations

import concurrent.futures
import json
import os
import secrets
from typing import Any, Dict, List, Optional, Sequence, Tuple, Union

from . import _native
from ._inputs import (
    Count,
    Exact,
    PathLike,
    Progress,
    Table,
    _count,
    _counts,
    _exact,
    _optional_exact,
    _path,
    _table,
    _threads,
    _total,
)
from ._keywords import in_package, public
from ._progress import _Bar, _run
from ._current import DrivenSweepResult
from ._results import FieldSweepResult, Result, SweepResult

#: A finished sweep of any kind.
Finished = Union[SweepResult, FieldSweepResult, DrivenSweepResult]

#: The result class and points' folder of each compiled sweep.
_KINDS = {
    "sweep": (SweepResult, "points"),
    "field_sweep": (FieldSweepResult, "field-points"),
    "driven_sweep": (DrivenSweepResult, "driven-points"),
}


@in_package
class ShardResult(Result):
    """One part of a sweep (``sweep(shard="I/N", out=DIR)``): ``shard`` (``index``, ``count``),
    ``points`` (the indices of the part's points, all finished in DIR), ``resumed_points``,
    ``config`` (the whole sweep's) and ``meta``. Merge every part with :func:`merge`."""

    def _summary(self) -> str:
        s = self["shard"]
        return (
            f"part {s['index']}/{s['count']}: points {self['points']} "
            f"({self['resumed_points']} resumed)"
        )


@public
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
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    electric: Optional[Sequence[Exact]] = None,
    electric_angle: Exact = 0,
    shard: Optional[str] = None,
    executor: Optional[concurrent.futures.Executor] = None,
) -> Union[Finished, ShardResult]:
    """D(w) over a grid of gaps (``lorentz sweep``), the diffusion tensor in a magnetic field
    over gaps and fields (``lorentz sweep --field`` / ``--fields``), or the driven gas over fields
    E at one gap (``lorentz sweep --electric``); whole, one part of it (``shard``), or spread over
    a process pool or cluster (``executor``).

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
        sweep.json and the figures (in a field: field-sweep.csv and field-sweep.json). With
        ``shard``: the part's points and manifest. With ``executor``: the merged points and tables.
    seed, threads, engine, checkpoint_every, progress
        As in :func:`diffusion`. With ``executor``, ``threads`` is per task (default 1).
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
    scene : {"triangular", "square"}, keyword only
        The lattice of a sweep in a field: the triangular one (at ``w`` or over ``w_from`` ..
        ``w_to``) or the square one at ``radius`` (a sweep over ``fields``: in a field its
        corridors close). A sweep over w without a field is the triangular scene's.
    radius : str, float, Fraction or Decimal, keyword only
        Disk radius of the square scene, 0 < radius < 1/2, taken exactly like ``w``.
    table : dict or path, keyword only
        A table given as data (as in :func:`diffusion`) for a sweep over ``fields`` on it, instead
        of ``scene``, ``w`` and ``radius``.
    electric : sequence of exact numbers, keyword only
        The fields E of a sweep of the driven gas at the gap ``w`` (a Gaussian-thermostatted
        electric field, 1/time, the speed staying 1; each 0 < abs(E) <= 10, exact like ``w``);
        with E and -E both given, J(-E) = -J(E) is checked.
    electric_angle : exact number, keyword only
        With ``electric``: the fields' angle from the x axis in degrees.
    shard : str, keyword only
        ``"I/N"``: compute only part I of N (point i belongs to part i mod N) into ``out``, as
        ``lorentz sweep --shard``; combine the N parts with :func:`merge`.
    executor : concurrent.futures.Executor, keyword only
        Spread the points over it (a ``ProcessPoolExecutor``, Dask's
        ``Client.get_executor()``, any ``concurrent.futures.Executor``): each point is a
        picklable call that runs the compiled sweep in the worker on the point's own seed
        streams, and the parts are merged here, with the bits of one process. The workers need
        no shared file system. Ctrl-C cancels the calls not yet started.

    Returns
    -------
    SweepResult
        ``rows`` (numpy structured array, one record per gap: ``w``, ``D`` ± ``D_err`` in
        length^2/time, ``D_MZ``, ``D_Bo``, the runs' F test), the same fields as attributes,
        ``run_D`` (points x runs), ``linear_fit``; ``to_pandas()``.
    FieldSweepResult
        In a field: ``rows`` with ``w`` (or ``radius`` on the square lattice), ``field``,
        ``D_xx`` ± ``D_xx_err``, the Hall ``D_xy`` ± ``D_xy_err`` (length^2/time), the exact and
        sampled localized shares and Kac's mean free time; ``onsager`` (the ±B checks) and
        ``onsager_agrees``; ``to_pandas()``.
    DrivenSweepResult
        With ``electric``: ``rows`` with ``w``, ``electric``, the mobility J/E ± its error
        (length²/time), the current, the Lyapunov pair and the sum rule per point; ``mobility``
        (per gap the polynomial χ² and the Einstein extrapolations to D), ``odd`` (the ±E
        checks) and ``odd_agrees``; ``to_pandas()``.
    ShardResult
        With ``shard``: the part's ``shard``, ``points`` and ``resumed_points``.
    """
    native, request, points = _request(
        w_from=w_from, w_to=w_to, steps=steps, runs=runs, collisions_per_run=collisions_per_run,
        batches_per_run=batches_per_run, seed=seed, checkpoint_every=checkpoint_every, w=w,
        field=field, fields=fields, localization_samples=localization_samples, scene=scene,
        radius=radius, table=table, electric=electric, electric_angle=electric_angle,
    )
    total = points * _total(_count("collisions_per_run", collisions_per_run)) * (
        _total(_count("runs", 10 if runs is None else runs)) if native == "sweep" else 1
    )
    request.update(threads=_threads(threads), engine=str(engine), out=_path(out), shard=shard)
    if executor is not None:
        if shard is not None:
            raise ValueError("shard and executor: give one (the executor runs every part itself)")
        if threads is None:
            request["threads"] = "1"
        return _scatter(native, request, executor, points, (total, progress))
    if shard is not None:
        if out is None:
            raise ValueError("shard: a part is written to out; give out=DIR (then merge the parts)")
        count = _shard_count(shard)
        total = total / points * len(range(_shard_index(shard), points, count)) if count else 0
    text = _run(getattr(_native, native), progress, total, "coll", request)
    if shard is not None:
        return ShardResult(text)
    return _KINDS[native][0](text)


def _request(
    *, w_from: Any, w_to: Any, steps: Any, runs: Any, collisions_per_run: Any,
    batches_per_run: Any, seed: Any, checkpoint_every: float, w: Any, field: Any, fields: Any,
    localization_samples: Any, scene: str, radius: Any, table: Any, electric: Any,
    electric_angle: Any,
) -> Tuple[str, Dict[str, Any], int]:
    """The compiled function of the sweep (``sweep`` over w, ``field_sweep`` in a field,
    ``driven_sweep`` under the thermostat), its keys but the run's (threads, engine, out, shard),
    and the number of points."""
    if electric is not None:
        return _driven_request(
            w=w, runs=runs, checkpoint_every=checkpoint_every, electric=electric,
            electric_angle=electric_angle, others=dict(
                w_from=w_from, w_to=w_to, field=field, fields=fields, radius=radius,
                table=table),
            counts=dict(collisions_per_run=collisions_per_run, batches_per_run=batches_per_run,
                        seed=seed),
        )
    if field is not None or fields is not None:
        if runs is not None:
            raise ValueError(
                "runs is not used by a sweep in a field (one run of collisions_per_run per point)"
            )
        if checkpoint_every != 60.0:
            raise ValueError(
                "checkpoint_every is not used by a sweep in a field (it resumes by point from out)"
            )
        if fields is not None and (isinstance(fields, (str, bytes)) or not fields):
            raise ValueError("fields: give a non-empty sequence of exact numbers, e.g. [-1, 1]")
        where = _table(scene, table, w=w, radius=radius, w_from=w_from, w_to=w_to)
        one_place = w is not None or radius is not None or table is not None
        points = (1 if fields is None else len(fields)) * (
            1 if one_place else int(_total(_count("steps", steps)))
        )
        return "field_sweep", {
            "scene": str(scene),
            "table": where,
            "w": _optional_exact("w", w),
            "radius": _optional_exact("radius", radius),
            "w_from": _optional_exact("w_from", w_from),
            "w_to": _optional_exact("w_to", w_to),
            **_counts(
                steps=steps,
                collisions_per_run=collisions_per_run,
                batches_per_run=batches_per_run,
                seed=seed,
                localization_samples=localization_samples,
            ),
            "field": _optional_exact("field", field),
            "fields": [] if fields is None else [_exact("fields", b) for b in fields],
        }, points
    if w is not None:
        raise ValueError(
            "w is the gap of a sweep over the field: give fields=[...] (a sweep over w: w_from, w_to)"
        )
    if scene != "triangular" or radius is not None or table is not None:
        raise ValueError(
            "a sweep over w without a field is the triangular scene's: scene, radius and table are "
            "for a sweep over the field (fields=[...])"
        )
    if w_from is None or w_to is None:
        raise ValueError("a sweep over w needs w_from and w_to")
    return "sweep", {
        "w_from": _exact("w_from", w_from),
        "w_to": _exact("w_to", w_to),
        **_counts(
            steps=steps,
            runs=10 if runs is None else runs,
            collisions_per_run=collisions_per_run,
            batches_per_run=batches_per_run,
            seed=seed,
        ),
        "checkpoint_every": float(checkpoint_every),
    }, int(_total(_count("steps", steps)))


def _driven_request(
    *, w: Any, runs: Any, checkpoint_every: float, electric: Any, electric_angle: Any,
    others: Dict[str, Any], counts: Dict[str, Any],
) -> Tuple[str, Dict[str, Any], int]:
    """The request of a sweep of the driven gas (``electric`` given) and its number of points."""
    given = [k for k, v in others.items() if v is not None]
    if given:
        raise ValueError(
            f"{given[0]}: a sweep of the driven gas runs over E at one gap; give w= and "
            "electric=[...] only"
        )
    if runs is not None or checkpoint_every != 60.0:
        what = "runs" if runs is not None else "checkpoint_every"
        raise ValueError(
            f"{what} is not used by a sweep of the driven gas (one run of collisions_per_run per "
            "point, resumed by point from out)"
        )
    if w is None:
        raise ValueError("w: a sweep of the driven gas needs its gap, e.g. w=0.2")
    if isinstance(electric, (str, bytes)) or not electric:
        raise ValueError("electric: give a non-empty sequence of exact numbers, e.g. [0.1, 0.2]")
    return "driven_sweep", {
        "w": _exact("w", w),
        "electric": [_exact("electric", e) for e in electric],
        "electric_angle": _exact("electric_angle", electric_angle),
        **_counts(**counts),
    }, len(electric)


def _shard_index(shard: str) -> int:
    try:
        return int(str(shard).split("/")[0])
    except ValueError:
        return 0


def _shard_count(shard: str) -> int:
    try:
        return int(str(shard).split("/")[1])
    except (ValueError, IndexError):
        return 0


def _part(native: str, request: Dict[str, Any]) -> str:
    """One part of a sweep, run in a worker: the compiled sweep ``native`` on ``request`` (its
    ``shard`` set, no ``out``), returning the part with its points (JSON). A module-level
    function, so that a process pool can pickle the call by name."""
    return getattr(_native, native)(request, None)


def _scatter(
    native: str,
    request: Dict[str, Any],
    executor: concurrent.futures.Executor,
    points: int,
    bar: Tuple[float, Progress],
) -> Finished:
    """The sweep with each of its ``points`` a call to ``executor`` (part i of ``points``), the
    parts merged here with the bits of one process (``_native.merge_parts``)."""
    if not callable(getattr(executor, "submit", None)):
        raise ValueError(
            "executor: give a concurrent.futures.Executor (a ProcessPoolExecutor, or Dask's "
            "client.get_executor())"
        )
    out = request["out"]
    total, progress = bar
    todo = _to_compute(native, out, points)
    texts: List[Optional[str]] = [None] * points
    with _Bar(progress, total / points * len(todo), "coll") as callback:
        futures = {
            executor.submit(_part, native, {**request, "out": None, "shard": f"{i}/{points}"}): i
            for i in todo
        }
        try:
            for f in concurrent.futures.as_completed(futures):
                texts[futures[f]] = f.result()
                if callback is not None:
                    callback(int(total / points))
        except BaseException:
            for f in futures:
                f.cancel()
            raise
    text = _native.merge_parts([t for t in texts if t is not None], out, request["threads"])
    return _KINDS[native][0](text)


def _to_compute(native: str, out: Optional[str], points: int) -> List[int]:
    """The points an executor computes: those without a file in ``out`` yet, and one of those
    with a file, drawn at random (operating-system entropy), computed again as the check of the
    files reused (``_native.merge_parts`` compares it to its file to the bit)."""
    if out is None:
        return list(range(points))
    folder = os.path.join(out, _KINDS[native][1])
    have = [os.path.isfile(os.path.join(folder, f"point-{i:04d}.json")) for i in range(points)]
    done = [i for i in range(points) if have[i]]
    check = [secrets.choice(done)] if done else []
    return [i for i in range(points) if not have[i]] + check


@public
def merge(
    shards: Sequence[PathLike],
    out: Optional[PathLike] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> Finished:
    """The parts of a sweep (the directories of ``sweep(shard="I/N", out=DIR)`` or ``lorentz
    sweep --shard``, all N, in any order) combined into the whole sweep (``lorentz merge``): the
    same bits as the sweep run in one piece, apart from ``meta`` and ``resumed_points``.

    Parameters
    ----------
    shards : sequence of paths
        The parts' directories. Every point is checked (sealed, of one sweep, on its grid), none
        may be missing or given twice: a refusal names the point and the part that owns it.
    out : path, optional
        Write the merged points (so that a sweep of the same settings with this ``out`` resumes
        them all) and the tables there.
    threads, progress
        As in :func:`diffusion`.

    Returns
    -------
    SweepResult, FieldSweepResult or DrivenSweepResult
        As :func:`sweep` returns for the whole sweep.
    """
    if isinstance(shards, (str, bytes, os.PathLike)):
        raise ValueError("shards: give a sequence of directories, e.g. ['p0', 'p1', 'p2']")
    text = _run(_native.merge, progress, None, "coll", {
        "shards": [_path(p) for p in shards],
        "out": _path(out),
        "threads": _threads(threads),
    })
    keys = json.loads(text)
    kind = "driven_sweep" if "odd" in keys else "field_sweep" if "onsager" in keys else "sweep"
    return _KINDS[kind][0](text)

"""One trajectory's events as a numpy structured array, for the caller's own observables."""

from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np

from . import _native
from ._inputs import Count, Exact, Progress, Table, _count, _optional_exact, _total, _where
from ._keywords import in_package, public
from ._progress import _Bar


#: The dtype of :func:`events`: one record per event.
EVENT_DTYPE = np.dtype(
    [
        ("t", np.float64),  # time since the start (speed 1: also the path length)
        ("x", np.float64),  # unwrapped world position after the event
        ("y", np.float64),
        ("vx", np.float64),  # velocity after the event (unit length)
        ("vy", np.float64),
        ("kind", "U9"),  # "start" (the first row), "collision" (a disk), "crossing" (an edge), "jump"
        ("collision", np.bool_),  # True: a collision with a disk; False: a crossing or the start
        ("obstacle", np.uint8),  # the disk (collision) or edge (crossing) label; 255 at the start
        ("i", np.int64),  # cell indices along the lattice vectors e1, e2
        ("j", np.int64),
        ("down", np.bool_),  # the cell's orientation (triangular lattice: a point-reflected trap)
    ]
)

_KINDS = np.array(["start", "collision", "crossing", "jump"])


def _event_array(cols: Dict[str, Any]) -> np.ndarray:
    out = np.empty(len(cols["t"]), dtype=EVENT_DTYPE)
    for name in EVENT_DTYPE.names:
        out[name] = _KINDS[cols["kind"]] if name == "kind" else cols[name]
    return out


@in_package
class Trajectory:
    """One trajectory's events, in as many chunks as memory asks for.

    ``Trajectory(w, seed=..., batch=b)`` is the trajectory of batch ``b`` of
    ``diffusion(w, seed=...)`` (with ``field``, of the field run: its start drawn from the
    diffusing orbits; ``scene="square", radius=r`` for the square lattice, ``table=`` for any
    periodic table given as data); ``start`` is its
    first row (``kind`` "start", t = 0) and each ``events(n)`` the next ``n`` events, with the
    same bits as one call for all of them (the state and the running time are kept between
    calls). ``time`` is the time of the last event so far.

    ``flights`` chooses how straight flights cross the lattice, as in :func:`lyapunov`:
    ``"walk"`` cell by cell, every edge crossing a row; ``"jump"`` a long flight straight to the
    cell of the first disk it can meet (the square lattice with 2**-32 <= radius <= 1/4, the
    triangular one beyond w_inf), one row of kind "jump" at the landing (the entered edge as its
    ``obstacle``) in place of the crossings it skips; ``"auto"`` jumps where that is faster
    (radius <= 1/8, w >= 6). The collisions are the walk's within the long-flight error model
    (``proofs-notes/long-flights.md``), not bit for bit; the attribute ``flights`` says which
    engine runs ("walk" or "jump"). A field's arcs always walk.

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
        table: Optional[Table] = None,
        field: Optional[Exact] = None,
        flights: str = "auto",
    ):
        self._stream = _native.EventStream({
            **_where(scene, table, w, radius),
            "seed": _count("seed", seed),
            "batch": _count("batch", batch),
            "field": _optional_exact("field", field),
            "flights": str(flights),
        })

    @property
    def start(self) -> np.ndarray:
        """The start as a one-row array of dtype :data:`EVENT_DTYPE` (t = 0, kind "start")."""
        return _event_array(self._stream.start())

    @property
    def flights(self) -> str:
        """The engine that runs: ``"jump"`` (long flights jumped) or ``"walk"``."""
        return self._stream.flights

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
        return f"<Trajectory at t = {self.time}, flights {self.flights}>"


@public
def events(
    w: Optional[Exact] = None,
    n: Count = 100_000,
    *,
    seed: Count = 1,
    batch: Count = 0,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    field: Optional[Exact] = None,
    flights: str = "auto",
    progress: Progress = None,
) -> np.ndarray:
    """One trajectory's start and its next ``n`` events, for your own observables.

    A numpy structured array of dtype :data:`EVENT_DTYPE` with ``n + 1`` rows: the start (row 0,
    ``kind`` "start", t = 0) and ``n`` consecutive events, each with ``t`` (time since the start),
    ``x``, ``y`` (unwrapped world position after the event), ``vx``, ``vy`` (velocity after it),
    ``kind`` ("collision" with a disk, "crossing" of a cell edge, or "jump", the landing of a
    long flight; ``collision`` the same as a bool), ``obstacle`` (the disk or edge label), ``i``, ``j``, ``down`` (the cell). The
    trajectory is batch ``batch`` of ``diffusion(w, seed=seed)`` (the same start), on the f64
    engine. With ``field`` (the magnetic field B, an exact decimal or fraction,
    1e-3 <= abs(B) <= 1e3; either lattice) the flights are arcs of radius 1/abs(B),
    counter-clockwise for B > 0, and the trajectory is batch ``batch`` of
    ``diffusion(w, field=B, seed=seed)`` (its start drawn from the diffusing orbits); ``t`` is
    then the arc time and ``x``, ``y`` the event points; ``field=0`` is the run without a field.
    ``table`` (a dict or the path of a TOML table file, as in :func:`diffusion`): any periodic
    table of disks instead of ``scene``, ``w`` and ``radius``.
    ``flights`` (``"auto"``, ``"walk"``, ``"jump"``): how straight flights cross the lattice, as
    for :class:`Trajectory`; ``"walk"`` gives every crossing. Memory is checked first:
    ``MemoryError`` names the largest n that fits; for more, continue one :class:`Trajectory` in
    chunks (the same bits)."""
    tr = Trajectory(w, seed=seed, batch=batch, scene=scene, radius=radius, table=table,
                    field=field, flights=flights)
    return np.concatenate([tr.start, tr.events(n, progress)])

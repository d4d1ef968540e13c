"""The Poincaré section in Birkhoff coordinates (``lorentz section``): where a magnetic field
makes phase space mixed, the regular islands drawn among the chaotic sea."""

from __future__ import annotations

from typing import Any, Dict, Optional

import numpy as np

from . import _native
from ._inputs import (
    Count,
    Exact,
    Progress,
    Table,
    _count,
    _counts,
    _optional_exact,
    _threads,
    _total,
    _where,
)
from ._keywords import in_package, public
from ._progress import _run
from ._results import Result

#: The components in drawing order (the sea first, under the rest) with their colours, as the
#: command line's figure draws them.
COLOURS = {
    "diffusing": "#b9b9b9",
    "skipping": "#1f77b4",
    "bounded": "#d62728",
}


@in_package
class SectionResult(Result):
    """A Poincaré section: one point per recorded collision in Birkhoff coordinates.

    Points (numpy arrays, one entry per collision): ``theta`` the polar angle of the contact
    point about its disk's centre in world coordinates (radians in [-pi, pi); the arc length
    is r * theta), ``p`` = sin of the angle of the outgoing velocity to the outward normal,
    counted counter-clockwise (the velocity's component along the counter-clockwise tangent, in
    [-1, 1]), ``trajectory`` (the trajectory's index) and ``disk`` (the disk among the table's disks of one
    cell). Per orbit: ``component`` (``"pinned"``, ``"skipping"``, ``"bounded"``: a regular
    island, ``"diffusing"``: the chaotic sea), ``reach`` (the largest distance from its start it
    reached, length) and ``ambiguous`` (a diffusing orbit within 4 excursion limits). Counts
    ``pinned``, ``skipping``, ``bounded``, ``diffusing``, ``ambiguous_trajectories``; ``limit`` the
    excursion limit (length; ``None`` without a field), ``field``, ``cyclotron_radius``.
    ``to_pandas()`` gives the points with their orbit's component, ``to_pandas("orbits")`` one record
    per orbit; ``plot()`` draws them."""

    _text_kind = "section"

    def __init__(self, text: str):
        super().__init__(text)
        d = self._data
        self.theta = np.asarray(d["theta"], dtype=np.float64)
        self.p = np.asarray(d["p"], dtype=np.float64)
        self.trajectory = np.asarray(d["trajectory"], dtype=np.int64)
        self.disk = np.asarray(d["disk"], dtype=np.int64)
        self.component = np.asarray(d["component"], dtype=str)
        self.reach = np.asarray(d["reach"], dtype=np.float64)
        self.ambiguous = np.asarray(d["ambiguous"], dtype=bool)
        self.limit = d.get("limit")
        self.field = d.get("field")
        self.cyclotron_radius = d.get("cyclotron_radius")

    def _summary(self) -> str:
        d = self._data
        where = d["scene"] + (f", B = {d['config']['field']}" if "field" in d["config"] else "")
        return (f"{d['pinned']} pinned, {d['skipping']} skipping, {d['bounded']} bounded, "
                f"{d['diffusing']} diffusing trajectories, {len(self.theta)} points on {where}")

    def points(self) -> np.ndarray:
        """The points as a numpy structured array: ``trajectory``, ``component`` (its trajectory's),
        ``disk``, ``theta`` (radians), ``p``."""
        out = np.zeros(len(self.theta), dtype=[("trajectory", np.int64), ("component", "U9"),
                                               ("disk", np.int64), ("theta", np.float64),
                                               ("p", np.float64)])
        out["trajectory"], out["disk"] = self.trajectory, self.disk
        out["theta"], out["p"] = self.theta, self.p
        out["component"] = self.component[self.trajectory] if len(self.trajectory) else []
        return out

    _default_table = "points"

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``points`` (:meth:`points`), and ``orbits``: one record per trajectory, its
        ``component``, ``reach`` (length) and ``ambiguous``."""
        orbits = np.zeros(len(self.component), dtype=[("component", "U9"), ("reach", np.float64),
                                                      ("ambiguous", np.bool_)])
        orbits["component"], orbits["reach"], orbits["ambiguous"] = (
            self.component, self.reach, self.ambiguous)
        return {"points": self.points(), "orbits": orbits}

    def plot(self, ax: Any = None) -> Any:
        """Draws the section with matplotlib on ``ax`` (a new figure's axes if ``None``):
        theta across [-pi, pi), p up [-1, 1], one dot per collision coloured by its
        orbit's component (diffusing light grey under skipping blue and bounded red), a legend
        with the number of orbits of each. Returns the axes."""
        if ax is None:
            import matplotlib.pyplot as plt

            _, ax = plt.subplots(figsize=(9, 6.5))
        comp = self.component[self.trajectory] if len(self.trajectory) else np.array([], dtype=str)
        for name, colour in COLOURS.items():
            n = int(np.sum(self.component == name))
            mask = comp == name
            ax.scatter(self.theta[mask], self.p[mask], s=2.0, c=colour, marker=".",
                       linewidths=0, rasterized=True,
                       label=f"{name}: {n} trajector{'y' if n == 1 else 'ies'}")
        ax.set_xlim(-np.pi, np.pi)
        ax.set_ylim(-1, 1)
        ax.set_xlabel("θ: polar angle of the contact point (radians; arc length s = rθ)")
        ax.set_ylabel("p = sin α (outgoing, counter-clockwise)")
        d = self._data
        field = d["config"].get("field")
        ax.set_title(f"Poincaré section, {d['scene']}" + (f", B = {field}" if field else ", no field"))
        legend = ax.legend(loc="lower right", markerscale=20, framealpha=0.9)
        legend.set_title(f"pinned: {d['pinned']}")
        return ax


@public
def section(
    w: Optional[Exact] = None,
    *,
    scene: str = "triangular",
    radius: Optional[Exact] = None,
    table: Optional[Table] = None,
    field: Optional[Exact] = None,
    trajectories: Count = 64,
    collisions: Count = 2000,
    classify_collisions: Count = 200_000,
    seed: Count = 1,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> SectionResult:
    """A Poincaré section in Birkhoff coordinates (``lorentz section``): each orbit's collisions
    as points (theta, p), coloured by the component of phase space it belongs to.

    Orbit i starts from the invariant measure on its own random stream (same seed, same bits at
    any thread count). In a field its cyclotron circle says exactly whether it is pinned (never
    collides: no points) or skipping (bounces round one disk for ever); any other orbit flies
    ``classify_collisions`` collisions and is bounded (a regular island) if the largest distance
    from its start stays within the excursion limit (a few cells plus a cyclotron diameter),
    diffusing (the chaotic sea) otherwise. Without a field every orbit is diffusing.

    Parameters
    ----------
    w : gap of the triangular scene (any w > 0 in a field); or ``scene="square"`` with
        ``radius`` (0 < radius < 1/2); or ``table``: any periodic table of disks, as in
        :func:`diffusion`. Exact as typed (``"0.2"``, ``"1/5"``).
    field : exact number, optional
        The magnetic field B (1/time; ``"5/2"``: cyclotron radius 0.4 in units of the disk
        radius); 0 or None: straight flights.
    trajectories : int
        Trajectories, 1 to 100000.
    collisions : int
        Collisions recorded per orbit (one point each), 1 to 1e7; trajectories * collisions <= 2e7.
    classify_collisions : int
        Collisions flown per orbit in a field to tell an island from the sea: at least
        ``collisions``, at most 1e10 (the default 2e5 takes a diffusing orbit at D = 0.005 well
        beyond the limit).
    seed, threads, progress
        As in :func:`diffusion`.

    Returns
    -------
    SectionResult
        ``theta`` (radians), ``p`` (dimensionless), ``trajectory``, ``disk`` per point; ``component``,
        ``reach`` (length), ``ambiguous`` per orbit; the counts; ``limit`` (length).

    Raises
    ------
    ValueError
        A bad table, field or count (the message names the valid range).

    Example
    -------
    >>> r = section(w=0.2, field="5/2", trajectories=64)  # doctest: +SKIP
    >>> r.plot()                                      # doctest: +SKIP
    """
    per_orbit = classify_collisions if field not in (None, 0, "0") else collisions
    total = _total(_count("trajectories", trajectories)) * _total(_count("collisions", per_orbit))
    text = _run(_native.section, progress, total, "coll", {
        **_where(scene, table, w, radius),
        "field": _optional_exact("field", field),
        **_counts(
            trajectories=trajectories,
            collisions=collisions,
            classify_collisions=classify_collisions,
            seed=seed,
        ),
        "threads": _threads(threads),
    })
    return SectionResult(text)

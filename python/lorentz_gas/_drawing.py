"""A trajectory picture: the disks of a scene and the flights of a trajectory (arcs in a
field) drawn on matplotlib axes (imported only when drawing)."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any, List, Optional, Tuple

import numpy as np


def _number(name: str, v: Any) -> float:
    """An exact decimal or fraction given as text, a Fraction or a number, as a float (drawing
    needs no more)."""
    try:
        return float(Fraction(str(v).strip())) if isinstance(v, str) else float(v)
    except (ValueError, ZeroDivisionError) as e:
        raise ValueError(f"{name} = {v!r} is not a number such as 0.1 or 1/10") from e


def lattice_disks(
    w: Any = None,
    *,
    scene: str = "triangular",
    radius: Any = None,
    xlim: Tuple[float, float],
    ylim: Tuple[float, float],
) -> List[Tuple[float, float, float]]:
    """The disks ``(x, y, r)`` of a scene that reach into the box ``xlim`` × ``ylim``.

    Triangular: disks of radius 1 at a(i + j/2, j√3/2), a = 2 + w (w > 0). Square: disks of
    radius ``radius`` (0 < radius < 1/2) at the integer points (lengths in lattice spacings)."""
    (x0, x1), (y0, y1) = sorted(map(float, xlim)), sorted(map(float, ylim))
    if scene == "triangular":
        if w is None or radius is not None:
            raise ValueError("the triangular scene takes w (the gap), not radius")
        gap = _number("w", w)
        if not gap > 0:
            raise ValueError(f"w = {w}: use w > 0 (the disks overlap at w <= 0)")
        a, r = 2.0 + gap, 1.0
        h = a * math.sqrt(3) / 2
        js = range(math.floor((y0 - r) / h), math.ceil((y1 + r) / h) + 1)
        centres = [
            (a * (i + j / 2), h * j)
            for j in js
            for i in range(math.floor((x0 - r) / a - j / 2), math.ceil((x1 + r) / a - j / 2) + 1)
        ]
    elif scene == "square":
        if radius is None or w is not None:
            raise ValueError("the square scene takes radius, not w")
        r = _number("radius", radius)
        if not 0 < r < 0.5:
            raise ValueError(f"radius = {radius}: use 0 < radius < 1/2")
        centres = [
            (float(i), float(j))
            for j in range(math.floor(y0 - r), math.ceil(y1 + r) + 1)
            for i in range(math.floor(x0 - r), math.ceil(x1 + r) + 1)
        ]
    else:
        raise ValueError(f"scene = {scene!r}: use 'triangular' or 'square'")
    return [
        (cx, cy, r)
        for cx, cy in centres
        if x0 - r <= cx <= x1 + r and y0 - r <= cy <= y1 + r
    ]


def draw_lattice(
    ax: Any,
    w: Any = None,
    *,
    scene: str = "triangular",
    radius: Any = None,
    xlim: Optional[Tuple[float, float]] = None,
    ylim: Optional[Tuple[float, float]] = None,
    **style: Any,
) -> List[Any]:
    """Draw the disks of a scene on matplotlib axes ``ax``, under a trajectory.

    Parameters
    ----------
    ax : matplotlib Axes
        Where to draw; its current limits are used unless ``xlim``/``ylim`` are given (plot the
        trajectory first, or pass the limits).
    w, scene, radius
        The scene as in :func:`diffusion` (``w`` for the triangular lattice, ``radius`` for the
        square one); lengths in disk radii (triangular) or lattice spacings (square).
    xlim, ylim : (float, float), optional
        The box to fill with disks (default: the axes' limits, which are then kept).
    **style
        Passed to each ``matplotlib.patches.Circle`` (default: light grey, no edge).

    Returns
    -------
    list of Circle
        The patches added. The axes get an equal aspect ratio, so disks look round.

    Examples
    --------
    >>> import matplotlib; matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt, lorentz_gas as lg
    >>> ev = lg.events(w="0.1", n=200)
    >>> fig, ax = plt.subplots()
    >>> _ = ax.plot(ev["x"], ev["y"], lw=0.8)
    >>> disks = lg.draw_lattice(ax, w="0.1")
    >>> len(disks) > 0
    True
    """
    from matplotlib.patches import Circle

    xlim = tuple(ax.get_xlim()) if xlim is None else xlim
    ylim = tuple(ax.get_ylim()) if ylim is None else ylim
    style = {"facecolor": "0.85", "edgecolor": "none", "zorder": 0, **style}
    patches = []
    for cx, cy, r in lattice_disks(w, scene=scene, radius=radius, xlim=xlim, ylim=ylim):
        patches.append(ax.add_patch(Circle((cx, cy), r, **style)))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    return patches


#: The dtype of :func:`arcs`: one record per flight between two consecutive events.
ARC_DTYPE = np.dtype(
    [
        ("t", np.float64),  # time of the flight's first event (its start)
        ("time", np.float64),  # the flight's time (speed 1: its length)
        ("x", np.float64),  # where the flight starts
        ("y", np.float64),
        ("vx", np.float64),  # the velocity it starts with (unit length)
        ("vy", np.float64),
        ("centre_x", np.float64),  # the centre of its circle (NaN: a straight flight)
        ("centre_y", np.float64),
        ("radius", np.float64),  # 1/|B| (inf: a straight flight)
        ("sense", np.int8),  # +1 counter-clockwise (B > 0), -1 clockwise (B < 0), 0 straight
        ("angle", np.float64),  # the angle turned, B * time (radians; 0 straight)
    ]
)

#: The largest angle (radians) between two points of a drawn arc.
_ARC_STEP = 0.05


def _field(field: Any) -> float:
    b = 0.0 if field is None else _number("field", field)
    if b != 0.0 and not 1e-3 <= abs(b) <= 1e3:
        raise ValueError(f"field = {field}: use 1e-3 <= abs(field) <= 1e3, or 0 (no field)")
    return b


def arcs(events: np.ndarray, field: Any = None) -> np.ndarray:
    """The flights between consecutive rows of :func:`events` (or :class:`Trajectory`), with
    the circle each one runs on in a magnetic field.

    Parameters
    ----------
    events : numpy structured array
        Rows of dtype :data:`EVENT_DTYPE` (at least ``t``, ``x``, ``y``, ``vx``, ``vy``), in
        time order: flight k runs from row k to row k + 1.
    field : str, float or Fraction, optional
        The field B the events were computed in (``events(..., field=B)``; 1e-3 <= abs(B) <=
        1e3); ``None`` or 0: straight flights.

    Returns
    -------
    numpy structured array of dtype :data:`ARC_DTYPE`
        One row per flight (``len(events) - 1``): its start ``t``, ``time``, start point ``x``,
        ``y`` and velocity ``vx``, ``vy``; in a field the ``centre_x``, ``centre_y`` of its
        cyclotron circle (the start point plus (−vy, vx)/B), ``radius`` 1/abs(B), ``sense`` +1
        (counter-clockwise, B > 0) or −1 (clockwise) and ``angle`` B·time turned; without one
        NaN centres, an infinite radius, sense 0 and angle 0.

    Examples
    --------
    >>> import lorentz_gas as lg
    >>> ev = lg.events(w="0.1", n=50, field="1/2")
    >>> a = lg.arcs(ev, field="1/2")
    >>> # Each arc ends at the next event: the centre plus the radius turned by the angle.
    >>> start = np.arctan2(a["y"] - a["centre_y"], a["x"] - a["centre_x"])
    >>> x_end = a["centre_x"] + a["radius"] * np.cos(start + a["angle"])
    >>> bool(np.allclose(x_end, ev["x"][1:], atol=1e-9))
    True
    >>> bool(np.all(a["radius"] == 2.0) and np.all(a["sense"] == 1))
    True
    """
    b = _field(field)
    ev = np.asarray(events)
    n = max(len(ev) - 1, 0)
    out = np.zeros(n, dtype=ARC_DTYPE)
    if n == 0:
        return out
    first = ev[:-1]
    out["t"] = first["t"]
    out["time"] = ev["t"][1:] - first["t"]
    for k in ("x", "y", "vx", "vy"):
        out[k] = first[k]
    if b == 0.0:
        out["centre_x"] = out["centre_y"] = np.nan
        out["radius"] = np.inf
        return out
    out["centre_x"] = first["x"] - first["vy"] / b
    out["centre_y"] = first["y"] + first["vx"] / b
    out["radius"] = 1.0 / abs(b)
    out["sense"] = 1 if b > 0 else -1
    out["angle"] = b * out["time"]
    return out


def _polyline(events: np.ndarray, field: Any = None) -> Tuple[np.ndarray, np.ndarray]:
    """The trajectory of :func:`events` as one polyline ``(x, y)`` to draw: the event points
    joined by straight segments, or in a ``field`` by their arcs, each drawn with a point at
    least every 0.05 radian (see :func:`arcs`). Lengths as in the events."""
    a = arcs(events, field)
    ev = np.asarray(events)
    if len(a) == 0 or a["sense"][0] == 0:
        return np.asarray(ev["x"], dtype=float), np.asarray(ev["y"], dtype=float)
    xs, ys = [], []
    for r in a:
        m = max(int(math.ceil(abs(r["angle"]) / _ARC_STEP)), 1)
        phi0 = math.atan2(r["y"] - r["centre_y"], r["x"] - r["centre_x"])
        phi = phi0 + np.linspace(0.0, r["angle"], m, endpoint=False)
        xs.append(r["centre_x"] + r["radius"] * np.cos(phi))
        ys.append(r["centre_y"] + r["radius"] * np.sin(phi))
    xs.append(np.asarray(ev["x"][-1:], dtype=float))
    ys.append(np.asarray(ev["y"][-1:], dtype=float))
    return np.concatenate(xs), np.concatenate(ys)


def draw_events(ax: Any, events: np.ndarray, field: Any = None, **style: Any) -> List[Any]:
    """Draw the trajectory of :func:`events` on matplotlib axes ``ax``: straight flights, or
    in a ``field`` their arcs, each drawn with a point at least every 0.05 radian; ``**style`` goes to ``ax.plot`` (default: a thin
    line). Returns the lines added; draw the disks under it with :func:`draw_lattice`.

    >>> import matplotlib; matplotlib.use("Agg")
    >>> import matplotlib.pyplot as plt, lorentz_gas as lg
    >>> ev = lg.events(w="0.1", n=100, field="1/2")
    >>> fig, ax = plt.subplots()
    >>> lines = lg.draw_events(ax, ev, field="1/2")
    >>> disks = lg.draw_lattice(ax, w="0.1")
    >>> len(lines)
    1
    """
    x, y = _polyline(events, field)
    return ax.plot(x, y, **{"lw": 0.8, **style})

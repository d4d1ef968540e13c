"""The lattice under a trajectory picture: the disks of a scene drawn on matplotlib axes."""

from __future__ import annotations

import math
from fractions import Fraction
from typing import Any, List, Optional, Tuple



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

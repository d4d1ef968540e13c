"""The paper's figures and the whole reproduction of the user guide, from this crate's numbers."""

from __future__ import annotations

import os
from typing import Optional

from . import _native
from ._inputs import Count, Exact, PathLike, Progress, _count, _optional_exact, _threads
from ._keywords import public
from ._progress import _Bar
from ._results import FigureResult, ReproduceResult


@public
def figure(
    kind: str,
    *,
    w: Optional[Exact] = None,
    particles: Optional[Count] = None,
    particles_per_gap: Optional[Count] = None,
    collisions_per_gap: Optional[Count] = None,
    seed: Count = 1,
    threads: Optional[Count] = None,
    out: PathLike = "results/figures",
    progress: Progress = None,
) -> FigureResult:
    """One of the paper's figures from this crate's numbers (``lorentz figure KIND``): PNG, SVG,
    CSV and JSON files written into ``out``.

    Parameters
    ----------
    kind : {"backscatter-map", "backscatter", "hierarchy"}
        ``"backscatter-map"``: Fig. 5, where injected particles backscatter, at one gap ``w``;
        ``"backscatter"``: Fig. 4a and its inset, p_bs(w) by injection on the paper's grid;
        ``"hierarchy"``: Figs. 3, 4b and 6, p_cf against App. A, D_cf, D_bs, the hierarchy and
        the exact lattice walks. (Figs. 2, 7 and 8 come from :func:`sweep`.)
    w : str, float, Fraction or Decimal, optional
        ``"backscatter-map"`` only: the gap (default 0.1), 0 < w < w_inf = 0.3094...
    particles : int, optional
        ``"backscatter-map"`` only: particles injected in all (default 60 000).
    particles_per_gap : int, optional
        ``"backscatter"`` only: particles injected at each gap of the grid (default 200 000).
    collisions_per_gap : int, optional
        ``"hierarchy"`` only: collisions at each gap, for the hop statistics and again for the
        Einstein D (default 2e7).
    seed : int
        Seed of the random streams (the same files for the same seed, on any number of threads).
    threads : int, optional
        Worker threads (default: every core this process may use).
    out : path
        Output directory (created if needed).
    progress : bool, callable or None
        As for :func:`diffusion`: units are injections or collisions.

    Returns
    -------
    FigureResult
        ``files`` (the names written into ``out``) and ``meta``.

    Raises
    ------
    ValueError
        A count given for another kind, or ``w`` for a figure on the paper's grid.
    """
    with _Bar(progress, 0, "units") as cb:
        text, printed = _native.figure({
            "kind": str(kind),
            "w": _optional_exact("w", w),
            "particles": None if particles is None else _count("particles", particles),
            "particles_per_gap": None if particles_per_gap is None
            else _count("particles_per_gap", particles_per_gap),
            "collisions_per_gap": None if collisions_per_gap is None
            else _count("collisions_per_gap", collisions_per_gap),
            "seed": _count("seed", seed),
            "threads": _threads(threads),
            "out": os.fspath(out),
        }, cb)
    return FigureResult(text, os.fspath(out), printed=printed)


@public
def reproduce(
    budget: str = "quick",
    *,
    seed: Count = 1,
    threads: Optional[Count] = None,
    out: PathLike = "results/reproduce",
    progress: Progress = None,
) -> ReproduceResult:
    """Every figure and table of the user guide, the paper's claims and speed against error,
    into ``out`` with an ``index.html`` (``lorentz reproduce``).

    Parameters
    ----------
    budget : {"quick", "paper"}
        ``"quick"``: minutes on 2 cores; ``"paper"``: the user guide's statistics (Fig. 8 at
        2e9 collisions per run), about an hour on 2 cores.
    seed : int
        Seed of the random streams.
    threads : int, optional
        Worker threads (default: every core this process may use).
    out : path
        Output directory; steps finished earlier at the same budget are kept, not redone, so an
        interrupted reproduction (Ctrl-C) continues where it stopped.
    progress : bool, callable or None
        As for :func:`diffusion`: units of work of each step (collisions, injections, steps).

    Returns
    -------
    ReproduceResult
        ``steps`` (each with ``name``, ``title``, ``seconds``, ``resumed`` and ``files``),
        ``budget``, ``meta``, and ``index``, the path of its ``index.html``.
    """
    with _Bar(progress, 0, "units") as cb:
        text, printed = _native.reproduce(
            {"budget": str(budget), "seed": _count("seed", seed), "threads": _threads(threads),
             "out": os.fspath(out)},
            cb,
        )
    return ReproduceResult(text, os.fspath(out), printed=printed)


# --- Drawings of results (``r.plot()``): matplotlib, imported only here -----------------------


def _axes(ax):
    """``ax``, or new axes of a new figure; matplotlib is imported only now."""
    try:
        import matplotlib.pyplot as plt
    except ImportError as e:
        raise ImportError(
            "plot() needs matplotlib, an optional dependency: pip install 'lorentz-gas[plot]' "
            "(or pip install matplotlib)"
        ) from e
    if ax is None:
        _, ax = plt.subplots()
    return ax


def plot_diffusion(r, ax=None):
    """The MSD of a diffusion result against time on log-log axes: the curve (``msd_curve``,
    with its errors) where the run kept one, else the MSD at ``msd_times``; and the line 4Dt of
    the fitted D. Returns the axes."""
    import numpy as np

    ax = _axes(ax)
    c = getattr(r, "msd_curve", None)
    if c is not None and len(c):
        t, m, e = c["times"], c["msd"], c["msd_err"]
    else:
        t, m, e = np.asarray(r.msd_times), r.msd, r.msd_err
    inside = t > 0  # t = 0 (MSD 0) has no place on log axes
    ax.errorbar(t[inside], m[inside], yerr=e[inside], fmt=".", ms=3, label="MSD")
    line = np.geomspace(t[inside].min(), t[inside].max(), 50)
    ax.plot(line, 4 * r.D * line, "--", lw=0.8, label=f"4Dt, D = {r.D:.5g}")
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("t")
    ax.set_ylabel("⟨Δr²⟩")
    ax.legend()
    return ax


def plot_free_paths(r, ax=None):
    """The free-path histogram of a result: each bin's probability density (probability over
    width, with its error) against the Boltzmann–Grad limit law's, over ξ = τ/⟨ℓ⟩; with
    ``free_path_samples``, their histogram on the same bins too. The open last bin is left
    out. Returns the axes."""
    import numpy as np

    ax = _axes(ax)
    b = r.bins[np.isfinite(r.bins["hi"])]
    width = b["hi"] - b["lo"]
    mid = (b["lo"] + b["hi"]) / 2
    ax.errorbar(mid, b["probability"] / width, xerr=width / 2,
                yerr=b["probability_err"] / width, fmt=".", label="measured")
    ax.stairs(b["limit"] / width, np.append(b["lo"], b["hi"][-1]), label="limit law (r → 0)")
    xi = np.asarray(getattr(r, "free_path_samples", []), dtype=float)
    if len(xi):
        counts, _ = np.histogram(xi, bins=np.append(b["lo"], b["hi"][-1]))
        ax.stairs(counts / len(xi) / width, np.append(b["lo"], b["hi"][-1]), ls=":",
                  label=f"{len(xi)} samples")
    ax.set_xlabel("ξ = τ/⟨ℓ⟩")
    ax.set_ylabel("probability density")
    ax.legend()
    return ax

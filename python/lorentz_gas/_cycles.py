"""The three-disk repeller by certified periodic orbits (``lorentz cycles``): every prime cycle
up to a length found by Newton's method in MPFR with a Newton-Kantorovich certificate, and the
cycle expansions of its escape rate, Lyapunov exponent, KS entropy and partial dimension."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Union

import numpy as np

from . import _native
from ._inputs import Count, Exact, Progress, _count, _counts, _exact, _threads, _total
from ._keywords import in_package, public
from ._progress import _run
from ._results import Result, _pm

#: The columns of a convergence table, as the JSON names them.
_TRUNCATION = ("max_length", "escape_rate", "escape_rate_error", "lyapunov", "lyapunov_error",
               "entropy", "entropy_error", "partial_dimension", "partial_dimension_error")


def _number(v: Any) -> float:
    """A number of the JSON, ``null`` (no estimate, as at N = 1) as NaN."""
    return np.nan if v is None else float(v)


def _truncations(rows: List[Dict[str, Any]]) -> np.ndarray:
    """A convergence table as a structured array: one record per N."""
    dtype = [(k, np.int64 if k == "max_length" else np.float64) for k in _TRUNCATION]
    return np.array(
        [tuple(r[k] if k == "max_length" else _number(r[k]) for k in _TRUNCATION) for r in rows],
        dtype=dtype,
    )


def _cycles(rows: List[Dict[str, Any]]) -> np.ndarray:
    """The cycles as a structured array: one record per fundamental-domain prime cycle."""
    width = max([len(r["word"]) for r in rows] + [1])
    dtype = [("word", f"U{width}"), ("length", np.int64), ("order", np.int64),
             ("period", np.float64), ("stability", np.float64),
             ("certificate_radius", np.float64), ("full_period", np.float64),
             ("period_bound", np.float64), ("full_stability", np.float64),
             ("stability_bound", np.float64), ("certified", np.bool_)]
    return np.array(
        [(r["word"], len(r["word"]), r["order"], _number(r["period"]), _number(r["stability"]),
          _number(r["cycle"]["radius"]), _number(r["cycle"]["period"]),
          _number(r["cycle"]["period_bound"]), _number(r["cycle"]["stability"]),
          _number(r["cycle"]["stability_bound"]), bool(r["cycle"]["certified"]))
         for r in rows],
        dtype=dtype,
    )


@in_package
class CyclesResult(Result):
    """The three-disk repeller by certified cycles.

    Per fundamental-domain prime cycle (numpy arrays, one entry per cycle, ordered by length):
    ``word`` (its binary symbols: 0 a reflection, 1 a rotation), ``order`` (the order h of the
    symmetry its full-space cycle closes with), ``period`` (T_p, time at speed 1: a length),
    ``stability`` (Λ_p, the expanding eigenvalue, signed) and ``certificate_radius`` (the true
    cycle lies within it of the computed one, in the l2 norm of the Birkhoff coordinates).
    The convergence table of the spectral determinant (one entry per truncation N = 1 ...
    max_length): ``N``, ``escape_rate`` (γ, 1/time), ``lyapunov`` (λ, 1/time), ``entropy``
    (h_KS = λ - γ, 1/time), ``partial_dimension`` (d, dimensionless), each with its truncation
    error ``<name>_error`` = abs(x_N - x_(N-1)) (NaN at N = 1); ``zeta_escape_rate`` and
    ``zeta_escape_rate_error``, the dynamical zeta function's. The tables as structured arrays:
    ``cycles`` (with ``length``, the full-space cycle's ``full_period`` T_p = h T_p̃ and
    ``full_stability`` Λ_p = Λ_p̃^h with their rigorous bounds ``period_bound`` and
    ``stability_bound``, and ``certified``), ``spectral_determinant``, ``zeta_function`` (``to_pandas()`` gives the
    determinant's, ``to_pandas("cycles")`` the cycles)."""

    _text_kind = "cycles"
    _default_table = "spectral_determinant"

    def __init__(self, text: str):
        super().__init__(text)
        d = self._data
        self.cycles = _cycles(d["cycles"])
        self.spectral_determinant = _truncations(d["spectral_determinant"])
        self.zeta_function = _truncations(d["zeta_function"])
        for k in ("word", "order", "period", "stability", "certificate_radius"):
            setattr(self, k, self.cycles[k].copy())
        det = self.spectral_determinant
        self.N = det["max_length"].copy()
        for k in _TRUNCATION[1:]:
            setattr(self, k, det[k].copy())
        self.zeta_escape_rate = self.zeta_function["escape_rate"].copy()
        self.zeta_escape_rate_error = self.zeta_function["escape_rate_error"].copy()

    def _summary(self) -> str:
        c = self._data["config"]
        if not len(self.N):
            return f"R = {c['side']}, a = {c['radius']}: no truncation"
        err = self.escape_rate_error[-1]
        error = "none" if np.isnan(err) else f"{err:.1e}"
        return (f"gamma = {self.escape_rate[-1]:.15f} (truncation error {error}) at N = "
                f"{self.N[-1]}, R = {c['side']}, a = {c['radius']}, "
                f"{self._data['certified']} cycles certified")


@in_package
class SurvivalResult(Result):
    """An open table's escape by survival (``lorentz escape --repeller`` or ``--open FILE``).

    Every key of the JSON as an attribute: ``gamma`` (the escape rate γ from the window at
    collision n0, 1/time), ``gamma_late`` (the next window's: the check), ``lyapunov`` (λ,
    1/time), ``entropy`` (h_KS = λ - γ, 1/time), ``mean_flight_time`` (⟨T⟩, time), each with
    its standard error over the batches ``<name>_err``; ``window_check_sigma``;
    ``transient_ratio`` and ``transient_bias`` (None before n0 = 3); ``survival`` (numpy array:
    the fraction of the particles alive at collision 0, 1, ..., n0 + 2). ``windows`` is a
    structured array with one record per window start n = 1 ... n0 + 1 (``start``, ``gamma``,
    ``gamma_err``, ``lyapunov``, ``lyapunov_err``); ``to_pandas()`` gives it."""

    _text_kind = "escape-survival"
    _default_table = "windows"

    def __init__(self, text: str):
        super().__init__(text)
        keys = ("start", "gamma", "gamma_err", "lyapunov", "lyapunov_err")
        dtype = [(k, np.int64 if k == "start" else np.float64) for k in keys]
        self.windows = np.array([tuple(r[k] for k in keys) for r in self._data["windows"]],
                                dtype=dtype)

    def _summary(self) -> str:
        return (f"gamma = {_pm(self.gamma, self.gamma_err)}, lambda = "
                f"{_pm(self.lyapunov, self.lyapunov_err)} on the {self.table}")


#: The columns of the lattice's convergence table, as the JSON names them.
_LATTICE_TABLE = ("max_length", "certified", "refused", "zeta", "mean_period", "mean_length",
                  "mean_square_winding", "diffusion", "mean_free_time", "change")


@in_package
class LatticeCyclesResult(Result):
    """The triangular Lorentz gas by certified cycles (``lorentz cycles --w``).

    Per certified prime cycle (numpy arrays, one entry per cycle, each C6v image its own entry,
    ordered by length): ``word`` (its letters: A-F the nearest neighbours at 0, 60, ... 300
    degrees, a-f the second neighbours at 30, 90, ... 330 degrees), ``length`` (collisions),
    ``winding`` (shape (n, 2): the lattice indices (i, j) of n̂_p, the disk reached after one
    period; the centre of disk (i, j) is (2 + w)(i + j/2, j√3/2)), ``period`` (T_p, time at speed 1), ``stability`` (Λ_p, the
    expanding eigenvalue, signed), ``certificate_radius`` (the true cycle lies within it of the
    computed one). The convergence table, one entry per truncation N = 1 ... max_length: ``N``,
    ``zeta`` (1/ζ(0,0), -> 0),
    ``mean_period`` (⟨T⟩_ζ), ``mean_length`` (⟨n⟩_ζ), ``mean_square_winding`` (⟨n̂²⟩_ζ, a
    squared length), ``diffusion`` (D_N = ⟨n̂²⟩_ζ/(4⟨T⟩_ζ), length²/time), ``mean_free_time``
    (⟨T⟩_ζ/⟨n⟩_ζ, against ``mean_free_time_exact``) and ``change`` (D_N - D_(N-1), NaN at N = 1).
    ``msd`` is the MSD's D beside it (a dict: ``D``, ``D_err``, ``difference_sigma``; None when not
    run). ``cycles`` and ``table`` are the structured arrays (``to_pandas()`` gives the table,
    with the prime cycles ``certified`` and ``refused`` of length <= N; ``to_pandas("cycles")``
    the cycles); ``refused`` lists the class representatives not certified (``word``,
    ``images``, ``stage``: screen, kernel, newton or certificate, and the ``reason``)."""

    _text_kind = "lattice-cycles"
    _default_table = "table"

    def __init__(self, text: str):
        super().__init__(text)
        d = self._data
        rows = []
        for c in d["cycles"]:
            for word, wind in zip(c["images"], c["image_windings"]):
                rows.append((word, len(word), wind[0], wind[1], _number(c["cycle"]["period"]),
                             _number(c["cycle"]["stability"]), _number(c["cycle"]["radius"])))
        width = max([len(r[0]) for r in rows] + [1])
        dtype = [("word", f"U{width}"), ("length", np.int64), ("i", np.int64), ("j", np.int64),
                 ("period", np.float64), ("stability", np.float64),
                 ("certificate_radius", np.float64)]
        self.cycles = np.array(rows, dtype=dtype)
        self.word = self.cycles["word"].copy()
        self.length = self.cycles["length"].copy()
        self.winding = np.stack([self.cycles["i"], self.cycles["j"]], axis=-1).reshape(-1, 2)
        for k in ("period", "stability", "certificate_radius"):
            setattr(self, k, self.cycles[k].copy())
        tdtype = [(k, np.int64 if k in ("max_length", "certified", "refused") else np.float64)
                  for k in _LATTICE_TABLE]
        self.table = np.array(
            [tuple(r[k] if k in ("max_length", "certified", "refused") else _number(r[k])
                   for k in _LATTICE_TABLE) for r in d["table"]], dtype=tdtype)
        self.N = self.table["max_length"].copy()
        for k in _LATTICE_TABLE[3:]:
            setattr(self, k, self.table[k].copy())

    def _summary(self) -> str:
        c = self._data["config"]
        if not len(self.N):
            return f"w = {c['w']}: no truncation"
        msd = self._data.get("msd")
        beside = "" if msd is None else f", MSD {msd['D']:.6f} ± {msd['D_err']:.6f}"
        return (f"D_N = {self.diffusion[-1]:.6f} at N = {self.N[-1]}, w = {c['w']}, "
                f"{len(self.word)} prime cycles certified{beside}")


@public
def cycles(
    *,
    side: Optional[Exact] = None,
    radius: Optional[Exact] = None,
    w: Optional[Exact] = None,
    max_length: Optional[Count] = None,
    bits: Optional[Count] = None,
    msd_collisions: Optional[Count] = None,
    threads: Optional[Count] = None,
    progress: Progress = None,
) -> Union[CyclesResult, LatticeCyclesResult]:
    """Certified periodic orbits and their cycle expansions (``lorentz cycles``): the
    three-disk repeller, or with ``w`` the triangular Lorentz gas.

    The repeller: three disks of radius a at the corners of an equilateral triangle of side R.
    Every prime cycle of the fundamental domain up to length ``max_length`` is found by Newton's
    method in MPFR and certified (Newton-Kantorovich: a unique true cycle within
    ``certificate_radius``, meeting every disk of its sequence and passing through no other,
    decided by the kernel); the spectral determinant and the dynamical zeta function, expanded
    in cycle length, give the escape rate, the mean Lyapunov exponent, the KS entropy and the
    partial dimension at every truncation N, each with its truncation error.

    The lattice (``w`` given): the cycles of the triangular Lorentz gas's elementary cell, words
    of lattice displacements to the 6 nearest and 6 second neighbours closed modulo the lattice
    with their windings, one per C6v class certified (its images share T_p and Λ_p), and the
    diffusion coefficient by the cycle-averaging formula D_N = ⟨n̂²⟩_ζ/(4⟨T⟩_ζ) at every
    truncation N, beside D from the MSD.

    Parameters
    ----------
    side : exact number
        R, the distance between the disk centres (a length): R > 2a. Exact as typed
        (``"6"``, ``"13/2"``, a ``Fraction``), rounded once at ``bits``. Default 6.
    radius : exact number
        a, the disk radius (a length): a > 0, exact as ``side``. Default 1.
    w : exact number
        The triangular Lorentz gas at this gap instead of the repeller (a length, disks of
        radius 1): 0 < w < w_inf = 4/√3 - 2 (a finite horizon), exact as typed.
    max_length : int
        The longest prime cycle N (the table has one row per N): the repeller's
        fundamental-domain cycles, 1 to 16 (default 8; N = 8 takes about a second, each N more
        about twice as long); the lattice's, in collisions, 1 to 7 (default 5).
    bits : int
        MPFR working precision of the cycles and their certificates, 128 to 4096 bits (default
        256 for the repeller, 128 for the lattice).
    msd_collisions : int
        With ``w``: collisions of the MSD run whose D stands beside the table, 1e6 to 1e11, or 0
        for none (default 2e8).
    threads, progress
        As in :func:`diffusion`; the result does not depend on ``threads``.

    Returns
    -------
    CyclesResult or LatticeCyclesResult
        The repeller's cycles (``word``, ``order``, ``period``, ``stability``,
        ``certificate_radius``) and convergence table (``N``, ``escape_rate``, ``lyapunov``,
        ``entropy``, ``partial_dimension`` with their ``_error``; ``zeta_escape_rate``); or the
        lattice's cycles (``word``, ``winding``, ``period``, ``stability``,
        ``certificate_radius``) and table (``N``, ``zeta``, ``diffusion``, ``change``, ...).

    Raises
    ------
    ValueError
        R <= 2a, a <= 0, w outside (0, w_inf), ``w`` with ``side`` or ``radius``, a length or
        precision out of range (the message names the valid range).

    Example
    -------
    >>> r = cycles(side=6, radius=1, max_length=6)  # doctest: +SKIP
    >>> r.escape_rate[-1]                            # doctest: +SKIP
    0.41033840...
    >>> cycles(w="1/10", max_length=4).diffusion     # doctest: +SKIP
    """
    if w is not None:
        if side is not None or radius is not None:
            raise ValueError("w (the triangular Lorentz gas) takes no side or radius (the "
                             "three-disk repeller): give one or the other")
        n = 5 if max_length is None else max_length
        text = _run(_native.lattice_cycles, progress, _prime_cycles(_count("max_length", n), 12, 7),
                    "cycles", {
            "w": _exact("w", w),
            **_counts(max_length=n,
                      bits=128 if bits is None else bits,
                      msd_collisions=int(2e8) if msd_collisions is None else msd_collisions),
            "threads": _threads(threads),
        })
        return LatticeCyclesResult(text)
    if msd_collisions is not None:
        raise ValueError("msd_collisions is an option of the triangular Lorentz gas (w=...): "
                         "the three-disk repeller has no MSD")
    max_length = 8 if max_length is None else max_length
    n = _count("max_length", max_length)
    text = _run(_native.cycles, progress, _prime_cycles(n), "cycles", {
        "side": _exact("side", 6 if side is None else side),
        "radius": _exact("radius", 1 if radius is None else radius),
        **_counts(max_length=max_length, bits=256 if bits is None else bits),
        "threads": _threads(threads),
    })
    return CyclesResult(text)


def _prime_cycles(max_length: str, letters: int = 2, longest: int = 16) -> Optional[float]:
    """The number of prime cycles over ``letters`` letters of length 1 to ``max_length`` (the
    units of work), or ``None`` where ``max_length`` is out of 1 ... ``longest`` (the compiled
    reader refuses it)."""
    try:
        n = int(_total(max_length))
    except (TypeError, ValueError):
        return None
    if not 1 <= n <= longest:
        return None

    def mobius(k: int) -> int:
        m, p, out = k, 2, 1
        while p * p <= m:
            if m % p == 0:
                m //= p
                if m % p == 0:
                    return 0
                out = -out
            p += 1
        return -out if m > 1 else out

    return float(sum(sum(mobius(d) * letters ** (m // d) for d in range(1, m + 1) if m % d == 0)
                     // m for m in range(1, n + 1)))

"""Result objects: the command line's JSON as attributes, numeric lists as numpy arrays."""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, List, Optional

import numpy as np


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _array(v: Any) -> Any:
    """A list of numbers (or a rectangular list of such lists) as a numpy array, else ``v``."""
    if isinstance(v, list) and v:
        if all(_is_number(x) for x in v):
            if all(isinstance(x, int) for x in v):
                return np.asarray(v, dtype=np.int64)
            return np.asarray(v, dtype=np.float64)
        if all(isinstance(x, list) and x and all(_is_number(y) for y in x) for x in v):
            if len({len(x) for x in v}) == 1:
                return np.asarray(v, dtype=np.float64)
    return v


def _pm(x: Optional[float], err: Optional[float]) -> str:
    if x is None or err is None:
        return "n/a"
    return f"{x:.6f} ± {err:.6f}"


def _with_error(x: float, err: float) -> str:
    """``x ± err`` with the error to two significant digits and the value to the same decimal
    place (``0.15229 ± 0.00011``), as ``lorentz report``'s headline writes it."""
    import math

    if not (math.isfinite(x) and math.isfinite(err) and err > 0):
        return f"{x} ± {err}"
    place = math.floor(math.log10(err)) - 1
    if not -6 <= place <= 6 or abs(x) >= 1e6:
        return f"{x:.4e} ± {err:.1e}"
    decimals = max(-place, 0)
    return f"{x:.{decimals}f} ± {err:.{decimals}f}"


def _scalars(data: Dict[str, Any]) -> List[tuple]:
    """(key, text) for the result's top-level scalars, each estimate with its ``_err`` as one
    ``x ± err`` entry (the ``_err`` key itself not repeated)."""
    out = []
    for k, v in data.items():
        if k.endswith("_err") and k[: -len("_err")] in data:
            continue
        err = data.get(f"{k}_err")
        if _is_number(v) and _is_number(err):
            out.append((k, _with_error(float(v), float(err))))
        elif _is_number(v) or isinstance(v, (str, bool)):
            out.append((k, str(v)))
    return out


class Result:
    """A result: every key of the command line's ``--json`` output as an attribute (numeric
    lists as numpy arrays), ``meta`` (how it was computed) as a dict, ``to_dict()`` and
    ``to_json()`` (the command line's JSON, digit for digit)."""

    _kind = "result"

    def __init__(self, text: str, *, printed: Optional[str] = None):
        self._json = text
        #: The command line's text of this result, where the call that made it rendered it.
        self._printed = printed
        self._data: Dict[str, Any] = json.loads(text)
        for k, v in self._data.items():
            setattr(self, k, _array(v))

    def keys(self) -> List[str]:
        """The result's keys, in the command line's order."""
        return list(self._data)

    def __getitem__(self, key: str) -> Any:
        return getattr(self, key)

    def to_dict(self) -> Dict[str, Any]:
        """The result as plain Python data (lists, not arrays): ``json.loads(self.to_json())``."""
        return copy.deepcopy(self._data)

    def to_json(self) -> str:
        """The command line's JSON of this result (``lorentz <command> --json``), unchanged."""
        return self._json

    def _summary(self) -> str:
        return ", ".join(self.keys()[:6]) + ", ..."

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self._summary()}>"

    def _meta_text(self) -> str:
        m = self._data.get("meta") or {}
        parts = [f"{k} {m[k]}" for k in ("seed", "batches", "precision", "engine", "threads")
                 if m.get(k) is not None]
        return ", ".join(parts)

    #: The result kind whose command-line text the library renders (``None``: not yet).
    _text_kind: Optional[str] = None

    def __str__(self) -> str:
        """The command line's text of this result (``lorentz <command>`` without ``--json``),
        where the library renders it; otherwise the summary line, every scalar of the result
        (estimates as ``x ± err`` to the place of their error) and how it was computed."""
        if self._printed is not None:
            return self._printed.rstrip("\n")
        if self._text_kind is not None:
            from . import _native

            try:
                text = _native.text(self._text_kind, self._json)
            except ValueError:
                # JSON the text cannot be read back from (a value JSON writes as null, such
                # as a NaN): the table below rather than no str() at all.
                text = None
            if text is not None:
                return text.rstrip("\n")
        rows = _scalars(self._data)
        width = max((len(k) for k, _ in rows), default=0)
        lines = [f"{type(self).__name__}: {self._summary()}"]
        lines += [f"  {k:<{width}}  {v}" for k, v in rows]
        if self._meta_text():
            lines.append(f"  ({self._meta_text()})")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The same as a table, for notebooks."""
        import html

        cells = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(v)}</td></tr>"
            for k, v in _scalars(self._data)
        )
        meta = html.escape(self._meta_text())
        return (
            f"<div><b>{html.escape(type(self).__name__)}</b>: {html.escape(self._summary())}"
            f"<table>{cells}</table><small>{meta}</small></div>"
        )

    def _tables(self) -> Dict[str, np.ndarray]:
        """The result's tables: its numpy structured arrays, by attribute name."""
        return {
            k: v for k, v in vars(self).items()
            if isinstance(v, np.ndarray) and v.dtype.names and not k.startswith("_")
        }

    def to_pandas(self, table: Optional[str] = None):
        """A table of the result as a ``pandas.DataFrame`` (needs pandas): its one table
        (``rows`` of a sweep, ...), the one named by ``table`` where there are several
        (``lags`` or ``limit_law`` of superdiffusion), or, without any, one row of its scalars
        (estimates and their errors as separate columns)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError(f"{type(self).__name__}.to_pandas() needs pandas: pip install pandas") from e
        tables = self._tables()
        if table is not None:
            if table not in tables:
                raise ValueError(f"table={table!r}: this result's tables are {sorted(tables) or 'none'}")
            return pd.DataFrame(tables[table])
        if len(tables) == 1:
            return pd.DataFrame(next(iter(tables.values())))
        if len(tables) > 1:
            raise ValueError(f"this result has several tables: name one with table= ({', '.join(sorted(tables))})")
        return pd.DataFrame([{k: v for k, v in self._data.items()
                              if _is_number(v) or isinstance(v, (str, bool))}])


class DiffusionResult(Result):
    """D(w) by the Einstein formula: ``D`` ± ``D_err`` (standard error over the batches, in
    units of length²/time with speed 1 and disk radius 1), the check window's ``D_check``, the
    mean free path against Santaló's ``mean_free_path_exact``, ``msd_times`` (time) and
    ``msd`` (⟨Δr²⟩, length²) as numpy arrays, ``batch_D`` (one D per batch). With
    ``msd_grid="log"``: ``msd_curve``, a table (numpy structured array, ``to_pandas()``) of
    ``times`` (time), ``msd`` (length²), ``vacf`` (⟨v(0)·v(t)⟩, 1 at t = 0) and ``green_kubo``
    (½∫₀ᵗ⟨v(0)·v(s)⟩ds, length²/time), each with ``_err``, from an eighth of the mean free time
    on; and ``D_green_kubo`` ± ``D_green_kubo_err`` with ``D_minus_D_green_kubo`` (paired).
    On your own times (``msd_grid=np.array([0, ...])``) the table starts at t = 0 and adds
    ``vacf_x``, ``vacf_y`` (⟨v_x(0)v_x(t)⟩, ⟨v_y(0)v_y(t)⟩: ½ each at t = 0). ``r.plot()``
    draws the MSD against 4Dt (matplotlib). ``print(r)`` shows the command line's text."""

    _text_kind = "diffusion"

    def plot(self, ax: Any = None) -> Any:
        """The MSD against time on log-log axes ``ax`` (new ones if ``None``), the curve where
        the run kept one, with the line 4Dt; returns the axes. Needs matplotlib."""
        from ._figures import plot_diffusion

        return plot_diffusion(self, ax)

    @property
    def msd(self) -> np.ndarray:
        """Mean squared displacement ⟨Δr²⟩ at ``msd_times`` (4 t · ``msd_over_4t``)."""
        return 4.0 * np.asarray(self.msd_times) * np.asarray(self.msd_over_4t)

    @property
    def msd_err(self) -> np.ndarray:
        """Standard error of ``msd`` over the batches."""
        return 4.0 * np.asarray(self.msd_times) * np.asarray(self.msd_over_4t_err)

    def __init__(self, text: str):
        super().__init__(text)
        curve = self._data.get("msd_curve")
        if isinstance(curve, dict):
            # One record per time of the logarithmic grid (a table: ``to_pandas()``).
            names = ["times", "msd", "msd_err", "vacf", "vacf_err", "green_kubo", "green_kubo_err"]
            names += [k for k in ("vacf_x", "vacf_x_err", "vacf_y", "vacf_y_err") if k in curve]
            n = len(curve.get("times") or [])
            table = np.zeros(n, dtype=[(k, np.float64) for k in names])
            for k in names:
                table[k] = [np.nan if x is None else x for x in curve.get(k) or []]
            self.msd_curve = table

    def collisions_for(self, rel_err: float) -> int:
        """The collisions (in this run's batches) that give the relative error ``rel_err`` of D
        (``1e-4`` is 0.01 %, from 1e-7 to 0.5): N·(r/rel_err)² for this run's N collisions and
        relative error r, rounded up to two significant digits and to a multiple of the batches —
        the library's planner, the one a ``rel_err=`` run applies to its pilot. The error falls
        as 1/sqrt(collisions)."""
        from . import _native

        batches = int(self.meta.get("batches") or 2)
        return _native.collisions_for(
            int(self.collisions), batches, self.D_err / abs(self.D), float(rel_err)
        )

    def seconds_for(self, rel_err: float) -> float:
        """How long :meth:`collisions_for` takes at this run's speed (seconds, on its threads)."""
        return self.collisions_for(rel_err) / self.collisions_per_second

    def _summary(self) -> str:
        return f"D = {_pm(self.D, self.D_err)} at w = {self.w}"


class TableDiffusionResult(Result):
    """D on a table given as data (``diffusion(table=...)``): ``D`` ± ``D_err`` (length²/time,
    the table's own lengths, speed 1), the check window's ``D_check``, ``identities`` (the mean
    free path against Santaló's closed form and the crossing time against pi|Q|/L, each with its
    Student-t statistic ``t``, its ``bound`` and ``agrees``), ``msd_times`` (time) and
    ``batch_D``; ``table``, the table as written. ``print(r)`` shows the command line's text."""

    _text_kind = "table-diffusion"

    def _summary(self) -> str:
        return f"D = {_pm(self.D, self.D_err)} on {self.scene}"


class FieldResult(Result):
    """The diffusion tensor in a magnetic field ``field``: ``D_xx`` and the Hall part ``D_xy``
    (length²/time, each with ``_err``) over the whole phase space, ``diffusing`` (a dict: the
    tensor of the part that is neither pinned nor skipping), the exact shares
    ``pinned_fraction_exact``, ``skipping_fraction_exact``, ``localized_fraction_exact`` and the
    sampled ``localized_fraction`` ± ``localized_fraction_err``, ``mean_free_time`` against Kac's
    ``mean_free_time_exact``, ``batch_D_xx`` and ``batch_D_xy`` (every batch), and
    ``components`` (a dict): which batches stayed ``bounded`` (within ``limit`` of their start:
    pinned, skipping or in a regular island) and were set aside, ``bounded_fraction`` ±
    ``bounded_fraction_err`` (below ``bounded_fraction_upper`` at 95 %), and ``split`` (the
    diffusing batches are not one component). ``D_xx`` and ``D_xy`` come from the diffusing
    batches only."""

    _text_kind = "field"

    def _summary(self) -> str:
        return (
            f"D_xx = {_pm(self.D_xx, self.D_xx_err)}, D_xy = {_pm(self.D_xy, self.D_xy_err)} "
            f"at {_scene_parameter(self._data)}, B = {self.field}"
        )


def _scene_parameter(d: dict) -> str:
    """``w = …`` of the triangular scene, ``radius = …`` of the square one."""
    return f"w = {d['w']}" if "w" in d else f"radius = {d.get('radius')}"


class FieldSweepResult(Result):
    """The diffusion tensor in a magnetic field over gaps and fields. ``rows`` is a numpy
    structured array, one record per point (gap-major), with ``w`` (``radius`` on the square
    lattice), ``field`` (B, 1/time),
    ``cyclotron_radius``, ``D_xx``, ``D_xx_err``, ``D_xy``, ``D_xy_err`` (the Hall part;
    length²/time), ``pinned_fraction_exact``, ``skipping_fraction_exact``,
    ``localized_fraction_exact``, ``localized_fraction``, ``localized_fraction_err``,
    ``all_localized``, ``mean_free_time`` ± ``mean_free_time_err`` and Kac's
    ``mean_free_time_exact``, and the point's ``bounded`` batches, ``bounded_fraction`` (±
    ``bounded_fraction_err``, below ``bounded_fraction_upper`` at 95 %) and ``split`` (its
    diffusing batches not one component); each field is also an attribute. ``onsager`` lists the ±B checks
    (``d_xx_even``, ``d_xy_odd``: difference, err, z, bound) and ``onsager_agrees`` their
    verdict; ``to_pandas()`` gives the table, ``to_pandas("onsager")`` the checks."""

    _text_kind = "field-sweep"

    def __init__(self, text: str):
        super().__init__(text)
        # One record per point: its numbers, and its components' share of bounded orbits (the
        # batch values and classification stay in ``to_dict()["rows"]``).
        raw = [_field_row(r) for r in self._data["rows"]]
        keys = list(raw[0].keys()) if raw else []
        dtype = [(k, np.bool_ if isinstance(raw[0][k], bool) else np.float64) for k in keys]
        self.rows = np.array([tuple(r[k] for k in keys) for r in raw], dtype=dtype)
        for k in keys:
            if k not in self._data:
                setattr(self, k, self.rows[k])

    def _tables(self) -> Dict[str, np.ndarray]:
        """``rows``, and ``onsager`` flattened: one record per ``|B|`` with ``w`` (or ``radius``),
        ``field`` and each check's ``difference``, ``err``, ``dof``, ``z`` and ``bound`` as
        ``d_xx_even_z``, ``d_xy_odd_bound``, ...."""
        tables = super()._tables()
        checks = self._data.get("onsager") or []
        if checks:
            flat = [
                {**{k: c[k] for k in ("w", "radius", "field") if k in c},
                 **{f"{name}_{k}": v for name in ("d_xx_even", "d_xy_odd")
                    for k, v in c[name].items()}}
                for c in checks
            ]
            keys = list(flat[0])
            tables["onsager"] = np.array([tuple(r[k] for k in keys) for r in flat],
                                         dtype=[(k, np.float64) for k in keys])
        return tables

    def to_pandas(self, table: Optional[str] = "rows"):
        """``rows`` as a ``pandas.DataFrame`` (needs pandas), or ``table="onsager"``: the ±B
        checks, one row per ``|B|``."""
        return super().to_pandas(table)

    def _summary(self) -> str:
        n = len(self.rows)
        verdict = "agree" if self.onsager_agrees else "DISAGREE"
        checks = f", Onsager-Casimir at {len(self.onsager)} |B|: {verdict}" if self.onsager else ""
        return f"{n} points in a field{checks}"


def _field_row(r: dict) -> dict:
    """A field sweep's row as scalars: its numbers and its ``components``' ``bounded``,
    ``bounded_fraction`` (± ``_err``, ``_upper``) and ``split``."""
    row = {k: v for k, v in r.items() if not isinstance(v, (list, dict))}
    c = r.get("components") or {}
    for k in ("bounded", "bounded_fraction", "bounded_fraction_err", "bounded_fraction_upper"):
        row[k] = float(c.get(k, 0.0))
    row["split"] = bool(c.get("split", False))
    return row


class HopsResult(Result):
    """Trap-hopping statistics: backscattering ``p_bs``, symbol-sequence probabilities
    ``pairs`` (with ``pairs_err``), the hop-level Green–Kubo ``D_GK`` against ``D_MZ``."""

    _text_kind = "hops"

    def _summary(self) -> str:
        return (
            f"p_bs = {_pm(self.p_bs, self.p_bs_err)}, D_GK = {_pm(self.D_GK, self.D_GK_err)} "
            f"at w = {self.w}"
        )


class TheoryResult(Result):
    """The corrected Machta–Zwanzig hierarchy: ``D_cf``, ``D_bs``, ``D_1`` and ``orders``
    (``D_k`` with errors) against the hop-level Green–Kubo ``D_GK`` and ``D_MZ``."""

    _text_kind = "theory"

    def _summary(self) -> str:
        return f"D_1 = {_pm(self.D_1, self.D_1_err)}, D_GK = {_pm(self.D_GK, self.D_GK_err)} at w = {self.w}"


class LatticeWalkResult(Result):
    """Correlated lattice walks of each order: ``walks`` (simulated and exact D) against
    ``D_GK``."""

    _text_kind = "lattice-walk"

    def _summary(self) -> str:
        return f"{len(self._data.get('walks', []))} walk orders, D_GK = {_pm(self.D_GK, self.D_GK_err)} at w = {self.w}"


class BackscatterResult(Result):
    """Backscattering by injection into one trap."""

    _text_kind = "backscatter"

    def _summary(self) -> str:
        p = self._data.get("p_bs")
        e = self._data.get("p_bs_err")
        return f"p_bs = {_pm(p, e)} at w = {self._data.get('w')}"


class SweepResult(Result):
    """D(w) over a grid of gaps. ``rows`` is a numpy structured array, one record per w, with
    the fields ``w``, ``inv_n`` (1/n, the area per disk), ``D``, ``D_err`` (standard error over
    the runs' batches), ``D_err_dof``, ``runs_f``, ``runs_f_dof1``, ``runs_f_dof2``,
    ``runs_p_value`` (the runs' spread against their errors), ``D_MZ``, ``D_Bo``, ``residual``;
    each field is also an attribute (``s.D``, ``s.w``); ``run_D`` and ``run_D_err`` are
    (points × runs) arrays; ``to_pandas()`` gives the table."""

    _text_kind = "sweep"

    def __init__(self, text: str):
        super().__init__(text)
        raw = self._data["rows"]
        scalar = [k for k, v in raw[0].items() if not isinstance(v, list)] if raw else []
        dtype = [(k, np.int64 if isinstance(raw[0][k], int) else np.float64) for k in scalar]
        self.rows = np.array([tuple(r[k] for k in scalar) for r in raw], dtype=dtype)
        for k in scalar:
            if k not in self._data:
                setattr(self, k, self.rows[k])
        for k in ("run_D", "run_D_err"):
            if raw and k in raw[0]:
                setattr(self, k, np.array([r[k] for r in raw], dtype=np.float64))

    def _summary(self) -> str:
        ws = self.rows["w"]
        return f"{len(ws)} points, w = {ws[0]} .. {ws[-1]}"


class EscapeResult(Result):
    """Diffusion from the escape rate out of open strips (Gaspard–Baras)."""

    _text_kind = "escape"

    def _summary(self) -> str:
        d = self._data
        return f"D = {_pm(d.get('D_escape'), d.get('D_escape_err'))} at w = {d.get('w')}"


class LyapunovResult(Result):
    """The largest Lyapunov exponent (``tangent``) and the divergence rows (``divergence``)."""

    _text_kind = "lyapunov"

    def _summary(self) -> str:
        t = self._data["tangent"]
        return (
            f"lambda = {_pm(t['per_collision'], t['per_collision_err'])} per collision, "
            f"{_pm(t['per_time'], t['per_time_err'])} per unit time"
        )


def _records(raw: List[Dict[str, Any]]) -> np.ndarray:
    """Rows of numbers (``None`` as NaN) and texts as a numpy structured array."""
    if not raw:
        return np.zeros(0)
    keys = list(raw[0])
    ints = [k for k in keys if all(isinstance(r[k], int) and not isinstance(r[k], bool) for r in raw)]
    texts = {k: max(len(r[k]) for r in raw) for k in keys if all(isinstance(r[k], str) for r in raw)}
    dtype = [(k, f"U{texts[k]}" if k in texts else np.int64 if k in ints else np.float64)
             for k in keys]
    return np.array(
        [tuple(np.nan if r[k] is None else r[k] for k in keys) for r in raw], dtype=dtype
    )


class SuperdiffusionResult(Result):
    """Superdiffusion in an infinite horizon against the exact corridor constants.

    The exact ``D_sup_exact`` (the limit law's variance of Δx/√(t ln t) and lim t·C_xx(t), in
    length²/time), ``C_flow_exact`` (P(τ > s) ≈ C_flow/s, time), ``C_map_exact``
    (μ(τ > s) ≈ C_map/s², time²), ``msd_log_slope_exact`` (2 D_sup) and the ``corridors``;
    the measured ``C_flow_tail``, ``C_map_tail``, ``D_sup_vacf``, ``msd_log_slope`` with their
    ``_err`` (``None`` for the tails when too few long flights were seen). ``lags`` is a numpy
    structured array, one record per lag t (time): ``t``, ``t_over_ell``, ``s_p_flow``,
    ``s2_p_map``, ``t_c``, ``msd_x`` (length²), ``msd_local_slope`` (NaN where the half lag is
    not on the grid), each with ``_err``, the unsampled-flight bounds ``s_p_flow_unsampled``, ``t_c_unsampled`` and
    ``msd_local_slope_unsampled``, and ``flights_longer``; ``limit_law`` likewise, one record
    per octave: ``t``, ``variance_ratio`` (→ 1), ``second_moment_ratio`` (→ 2), each with
    ``_err``, ``ks_distance``, ``samples``."""

    _text_kind = "superdiffusion"

    def __init__(self, text: str):
        super().__init__(text)
        self.lags = _records(self._data["lags"])
        self.limit_law = _records(self._data["limit_law"])

    def _summary(self) -> str:
        d = self._data
        return (
            f"D_sup_vacf = {_pm(d['D_sup_vacf'], d['D_sup_vacf_err'])} against "
            f"D_sup = {d['D_sup_exact']:.6f} on {d['scene']}"
        )


class FreePathResult(Result):
    """The free path between collisions, ξ = τ/ℓ (ℓ Santaló's mean free path, dimensionless),
    against the Boltzmann–Grad limit law of small disks.

    ``mean`` (exactly 1 at every radius; ``mean_check`` its comparison), ``ln_mean`` against
    ``ln_mean_limit`` = 27ζ(3)/(2π²) − 3 ln 2, each with ``_err``; ``longest`` ξ;
    ``max_z`` over the bins against ``max_z_bound``. ``bins`` is a numpy structured
    array, one record per bin of ξ: ``lo``, ``hi`` (NaN for the open last bin),
    ``probability`` ± ``probability_err``, the limit law's ``limit`` and ``z`` (on the
    ``bins=`` edges given); ``free_path_samples``, the ξ kept (``keep_samples=``). ``r.plot()``
    draws the histogram against the limit law (matplotlib)."""

    _text_kind = "free-paths"

    def plot(self, ax: Any = None) -> Any:
        """The histogram's probability densities against the limit law's (and the samples' on
        the same bins) on axes ``ax`` (new ones if ``None``); returns the axes. Needs
        matplotlib."""
        from ._figures import plot_free_paths

        return plot_free_paths(self, ax)

    def __init__(self, text: str):
        super().__init__(text)
        self.bins = _records(self._data["bins"])
        #: The ξ kept (``keep_samples``): an empty array if none were.
        self.free_path_samples = np.asarray(self._data.get("free_path_samples", []), dtype=float)

    def _summary(self) -> str:
        d = self._data
        return (
            f"<xi> = {_pm(d['mean'], d['mean_err'])} (exact 1), <ln xi> = "
            f"{_pm(d['ln_mean'], d['ln_mean_err'])} (limit {d['ln_mean_limit']:.6f}) on {d['scene']}"
        )


class AuditResult(Result):
    """A shadow audit: the events replayed in MPFR and how many fell outside the error model."""

    _text_kind = "audit"

    def _summary(self) -> str:
        s = self._data["summary"]
        out = f"{s['audited']} events replayed, {s['outside']} outside the error model"
        j = s.get("jumps") or {}
        if j.get("audited"):
            out += f"; {j['audited']} jumps replayed, {j['outside']} outside their model"
        return out


class BenchResult(Result):
    """The engine's throughput here: ``collisions_per_second`` (median over the repetitions, all
    threads), ``collisions_per_second_per_thread``, ``ns_per_collision`` (per thread), each
    repetition's rate in ``samples``, and on the SIMD engine ``divider_bound`` (what the divide
    and square-root unit alone allows)."""

    _text_kind = "bench"

    def __init__(self, text: str):
        super().__init__(text)
        if "rows" in self._data:
            self._text_kind = "bench-long-flights"
            # One record per radius (or gap); each repetition's timings stay in
            # ``to_dict()["rows"]``.
            self.rows = _records([{k: v for k, v in r.items() if not isinstance(v, list)}
                                  for r in self._data["rows"]])

    def _summary(self) -> str:
        d = self._data
        if "rows" in d:
            return ", ".join(
                (f"r = {r['radius']}" if "radius" in r else f"w = {r['w']}")
                + f": {r['ns_per_collision']:.1f} ns/collision"
                for r in d["rows"]
            ) + " (long flights jumped, one thread)"
        return (
            f"{d['collisions_per_second_per_thread']:.3e} collisions/s per thread "
            f"({d['ns_per_collision']:.2f} ns/collision) on {d['threads']} thread(s)"
        )


class ShadowResult(Result):
    """True orbits shadowing f64 segments (Newton's method, certified by Kantorovich)."""

    _text_kind = "shadow"

    def _summary(self) -> str:
        d = self._data
        return f"{len(d['segments'])} segments: {d['converged']} converged, {d['certified']} certified"


class CertifyResult(Result):
    """A segment of an equilibrium trajectory certified to its digits."""

    _text_kind = "certify"

    def _summary(self) -> str:
        d = self._data
        return f"{d['collisions']} collisions certified to {d['digits_agreed']:.1f} digits"


class TrajectoryResult(Result):
    """One trajectory from exact inputs: ``x``, ``y`` and ``distance`` are decimal strings
    carrying exactly the certified digits; ``events`` (when asked) the events as dicts."""

    def _summary(self) -> str:
        d = self._data
        return f"x = {d['x']}, y = {d['y']} ({d['certified_digits']} digits certified)"


class ReportResult(Result):
    """The publication audit of a result file: ``verdict`` (PASS: every check that applies ran
    and passed; FAIL: one failed; INCOMPLETE: none failed but some were skipped, so the result is
    not verified) and ``checks`` (each PASS, FAIL, SKIP or N/A, with its reason)."""

    def _summary(self) -> str:
        d = self._data
        return f"{d['verdict']}: {len(d['checks'])} checks"


class FigureResult(Result):
    """A figure of the paper (``lorentz figure``): ``files``, the names written into ``out``
    (PNG, SVG, CSV, JSON), and ``meta``."""

    def __init__(self, text: str, out: str = ".", *, printed: Optional[str] = None):
        super().__init__(text, printed=printed)
        #: The folder the files were written into.
        self.out = out

    def paths(self) -> List[str]:
        """The files' paths (``out`` joined with each name)."""
        import os

        return [os.path.join(self.out, f) for f in self._data.get("files", [])]

    def _summary(self) -> str:
        return f"{len(self._data.get('files', []))} files in {self.out}"


class ReproduceResult(Result):
    """A reproduction of the user guide (``lorentz reproduce``): ``steps`` (each with ``name``,
    ``title``, ``seconds``, ``resumed``, ``files``), ``budget`` and ``meta``; ``index`` is the
    path of its ``index.html``."""

    def __init__(self, text: str, out: str = ".", *, printed: Optional[str] = None):
        super().__init__(text, printed=printed)
        import os

        #: The folder of the reproduction.
        self.out = out
        #: Its front page.
        self.index = os.path.join(out, "index.html")

    def _summary(self) -> str:
        steps = self._data.get("steps", [])
        resumed = sum(1 for s in steps if s.get("resumed"))
        return f"{len(steps)} steps ({resumed} resumed), {self.index}"


class ConstantsResult(Result):
    """The closed forms of one scene (``lorentz constants``): lengths in disk radii (triangular)
    or lattice spacings (square), times at speed 1."""

    def _summary(self) -> str:
        d = self._data
        where = _scene_parameter(d)
        mfp = d.get("mean_free_path")
        return f"{where}: mean free path {mfp}" + (f", D_MZ = {d['D_MZ']}" if "D_MZ" in d else "")


class ConstantsTable:
    """The closed forms of several scenes: ``results`` (one :class:`ConstantsResult` each, in
    order), every scalar constant they share as a numpy array attribute (``t.w``, ``t.D_MZ``,
    ``t.mean_free_path``), ``rows`` (a numpy structured array of them) and ``to_pandas()``."""

    def __init__(self, results: List[ConstantsResult]):
        self.results = results
        keys = [k for k, v in results[0].to_dict().items() if _is_number(v)] if results else []
        keys = [k for k in keys if all(_is_number(r.to_dict().get(k)) for r in results)]
        self.rows = np.array(
            [tuple(r.to_dict()[k] for k in keys) for r in results],
            dtype=[(k, np.float64) for k in keys],
        )
        for k in keys:
            setattr(self, k, self.rows[k])

    def __len__(self) -> int:
        return len(self.results)

    def to_pandas(self):
        """``rows`` as a ``pandas.DataFrame`` (needs pandas)."""
        import pandas as pd

        return pd.DataFrame(self.rows)

    def __repr__(self) -> str:
        return f"<ConstantsTable: {len(self)} scenes, {', '.join(self.rows.dtype.names or ())}>"

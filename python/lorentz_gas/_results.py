"""Result objects: the command line's JSON as attributes, numeric lists as numpy arrays."""

from __future__ import annotations

from typing import Any, Dict, List, Optional

import numpy as np

from . import _tables
from ._result_base import Result, _is_number, _pm  # noqa: F401  (Result: the package's base)


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
    draws the MSD against 4Dt (matplotlib).
    Tables: ``to_pandas("batches")`` (one row per batch: ``D``, ``D_check``) and
    ``to_pandas("msd")`` (one row per time of the MSD grid). ``print(r)`` shows the command
    line's text."""

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

    def _more_tables(self) -> Dict[str, np.ndarray]:
        return _msd_and_batches(self._data)

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


def _msd_and_batches(d: Dict[str, Any]) -> Dict[str, np.ndarray]:
    """``msd``: one record per time of the MSD grid, ``times`` (time), ``msd_over_4t``
    (length²/time) with its ``_err``, ``msd`` and ``msd_err`` (length²); ``batches``: one record
    per batch, its ``D`` and ``D_check`` (length²/time)."""
    times = np.asarray(d.get("msd_times") or [], dtype=np.float64)
    m = np.asarray(d.get("msd_over_4t") or [], dtype=np.float64)
    e = np.asarray(d.get("msd_over_4t_err") or [], dtype=np.float64)
    msd = None
    if len(times) == len(m) == len(e):
        msd = _tables.columns(times=times, msd_over_4t=m, msd_over_4t_err=e,
                              msd=4 * times * m, msd_err=4 * times * e)
    return {"msd": msd, "batches": _tables.columns(
        batch=list(range(len(d.get("batch_D") or []))),
        D=d.get("batch_D"), D_check=d.get("batch_D_check"))}


class TableDiffusionResult(Result):
    """D on a table given as data (``diffusion(table=...)``): ``D`` ± ``D_err`` (length²/time,
    the table's own lengths, speed 1), the check window's ``D_check``, ``identities`` (the mean
    free path against Santaló's closed form and the crossing time against pi|Q|/L, each with its
    Student-t statistic ``t``, its ``bound`` and ``agrees``), ``msd_times`` (time) and
    ``batch_D``; ``table``, the table as written. ``print(r)`` shows the command line's text."""

    _text_kind = "table-diffusion"

    def _more_tables(self) -> Dict[str, np.ndarray]:
        return _msd_and_batches(self._data)

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

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``batches``: one record per batch, ``D_xx`` and ``D_xy`` (length²/time), its
        ``component`` and ``reach`` (the farthest it got from its start, length)."""
        d, c = self._data, self._data.get("components") or {}
        return {"batches": _tables.columns(
            batch=list(range(len(d.get("batch_D_xx") or []))), D_xx=d.get("batch_D_xx"),
            D_xy=d.get("batch_D_xy"), component=c.get("batch_component"),
            reach=c.get("batch_reach"))}

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

    _default_table = "rows"

    def to_pandas(self, table: Optional[str] = "rows"):
        """``rows`` as a ``pandas.DataFrame`` (needs pandas), or ``table="onsager"``: the ±B
        checks, one row per ``|B|``, with ``w`` (or ``radius``), ``field`` and each check's
        ``difference``, ``err``, ``dof``, ``z`` and ``bound`` as ``d_xx_even_z``,
        ``d_xy_odd_bound``, ...."""
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

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``pairs`` and ``sequences``: one record per symbol sequence, its probability
        ``value`` and ``err``; ``correlations``: one record per lag j (hops), C_j with ``err``."""
        d = self._data
        c = d.get("correlations") or []
        return {
            "pairs": _tables.keyed(d.get("pairs") or {}, d.get("pairs_err") or {}, key="sequence"),
            "sequences": _tables.keyed(d.get("sequences") or {}, d.get("sequences_err") or {},
                                       key="sequence"),
            "correlations": _tables.columns(lag=list(range(1, len(c) + 1)), value=c,
                                            err=d.get("correlations_err")),
        }

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

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``runs``: one record per run of each point, its ``w``, ``run`` (index), ``D`` and
        ``D_err`` (length²/time)."""
        return {"runs": _tables.records([
            {"w": r["w"], "run": i, "D": x, "D_err": e}
            for r in self._data["rows"]
            for i, (x, e) in enumerate(zip(r.get("run_D") or [], r.get("run_D_err") or []))
        ])}

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

    def __init__(self, text: str):
        super().__init__(text)
        #: One record per precision: ``precision``, ``starts``, the ``horizon`` (collisions) and
        #: the divergence rate per collision and per unit time, each with ``_err``.
        #: (In a field there is none: ``tangent`` only.)
        if "divergence" in self._data:
            self.divergence = _tables.records(self._data["divergence"])
        #: Under the thermostat (``electric=``): ``lambda_plus``, ``lambda_minus`` (1/time),
        #: ``contraction`` (⟨α⟩ = E·J), ``kaplan_yorke``, each with ``_err``, and ``sum_rule``.
        if "sum_rule" in self._data:
            self._text_kind = "lyapunov-driven"

    def _summary(self) -> str:
        t = self._data["tangent"]
        if "sum_rule" in self._data:
            d = self._data
            return (
                f"lambda+ = {_pm(d['lambda_plus'], d['lambda_plus_err'])}, "
                f"lambda- = {_pm(d['lambda_minus'], d['lambda_minus_err'])} per unit time, "
                f"Kaplan-Yorke {_pm(d['kaplan_yorke'], d['kaplan_yorke_err'])}"
            )
        return (
            f"lambda = {_pm(t['per_collision'], t['per_collision_err'])} per collision, "
            f"{_pm(t['per_time'], t['per_time_err'])} per unit time"
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
        self.lags = _tables.records(self._data["lags"])
        self.limit_law = _tables.records(self._data["limit_law"])

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
        self.bins = _tables.records(self._data["bins"])
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

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``quantiles``: one record per error measure (``error``), its ``median``, ``p99`` and
        ``max``."""
        return {"quantiles": _tables.keyed(self._data.get("quantiles") or {}, key="error")}

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
            self.rows = _tables.records([{k: v for k, v in r.items() if not isinstance(v, list)}
                                  for r in self._data["rows"]])
        elif "thermostat_over_straight" in self._data:
            self._text_kind = "bench-electric"

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``samples``: one record per repetition, its ``collisions_per_second``."""
        s = self._data.get("samples")
        return {"samples": _tables.columns(repetition=list(range(len(s))),
                                           collisions_per_second=s) if s else None}

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

"""The result of a run under the thermostatted electric field (``diffusion(electric=...)``)."""

from __future__ import annotations

from typing import Dict

import numpy as np

from . import _tables
from ._result_base import Result, _pm


class CurrentResult(Result):
    """The steady state under a Gaussian-thermostatted electric field E (``electric``, at
    ``electric_angle`` degrees): the current ``J_x``, ``J_y`` and its parts along and across E,
    ``J_parallel`` and ``J_perp`` (length/time, speed 1), the mobility ``mobility`` = J_parallel/E
    (length²/time; the Einstein relation makes it tend to the field-free D as E → 0), the entropy
    production ``entropy_production`` = E·J = the mean phase-space contraction rate (1/time),
    each with ``_err`` (standard error over batches); ``diffusion`` and ``diffusion_check`` (dicts:
    the tensor about the drift, ``D_xx``, ``D_yy``, ``D_xy``, ``D_parallel``, ``D_perp`` with
    ``_err``, over the fit and check windows); ``angle_bins`` (radians from E), ``angle_density``
    ± ``angle_density_err`` (per radian); ``mean_free_time`` ± ``mean_free_time_err`` beside the
    field-free ``mean_free_time_no_field``; ``batch_J_parallel``, ``batch_J_perp``.
    ``to_pandas()`` gives the batches, ``to_pandas("angles")`` the angle's distribution."""

    _text_kind = "current"

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """``batches``: ``J_parallel`` and ``J_perp`` per batch (length/time); ``angles``: the
        velocity angle's density per radian by bin centre (radians from E)."""
        d = self._data
        return {
            "batches": _tables.columns(
                batch=list(range(len(d.get("batch_J_parallel") or []))),
                J_parallel=d.get("batch_J_parallel"), J_perp=d.get("batch_J_perp")),
            "angles": _tables.columns(
                angle=d.get("angle_bins"), density=d.get("angle_density"),
                density_err=d.get("angle_density_err")),
        }

    def _summary(self) -> str:
        return (
            f"J/E = {_pm(self.mobility, self.mobility_err)}, "
            f"J = ({_pm(self.J_x, self.J_x_err)}, {_pm(self.J_y, self.J_y_err)}) "
            f"at E = {self.electric} on {self.scene}"
        )


class DrivenSweepResult(Result):
    """The driven gas over fields E (``sweep(w=..., electric=[...])``, ``lorentz sweep
    --electric``). ``rows`` is a numpy structured array, one record per point (gap-major): ``w``,
    the signed field ``electric`` (1/time; the speed is 1) at ``electric_angle`` degrees, and the
    steady state as in :class:`CurrentResult` — ``J_parallel``, ``J_perp`` (length/time),
    ``mobility`` = J_parallel/abs(E) (length²/time, along each point's own field),
    ``entropy_production``, ``lambda_plus``, ``lambda_minus``, ``sum_rule``, ``kaplan_yorke``,
    ``mean_free_time``, each with ``_err``, and the tensor about the drift as ``diffusion_D_xx``
    … ``diffusion_D_perp_err``. ``mobility`` (the attribute) lists per gap the χ² of polynomials
    in abs(E) through the mobilities (``polynomial_chi2``) and the Einstein extrapolations
    ``einstein_linear`` (J/E = D + a·abs(E)) and ``einstein_quadratic`` (D + c·E²), whose
    ``intercept`` ± √``var_intercept`` is D; ``odd`` the J(−E) = −J(E) checks and ``odd_agrees``
    their verdict. ``to_pandas()`` gives the rows, ``to_pandas("odd")`` the checks."""

    _text_kind = "driven-sweep"
    _default_table = "rows"

    def __init__(self, text: str):
        super().__init__(text)
        self.rows = _tables.records(self._data["rows"])

    def _summary(self) -> str:
        n = len(self.rows)
        verdict = "agree" if self.odd_agrees else "DISAGREE"
        checks = f", J(-E) = -J(E) at {len(self.odd)} |E|: {verdict}" if self.odd else ""
        fits = [m["einstein_linear"] for m in self.mobility if m.get("einstein_linear")]
        einstein = ""
        if fits:
            f = fits[0]
            einstein = f", D + a|E| extrapolates to {_pm(f['intercept'], f['var_intercept'] ** 0.5)}"
        return f"{n} points of the driven gas{einstein}{checks}"

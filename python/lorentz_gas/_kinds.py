"""Every kind of result the command line writes, each recognised by keys only it has: the kind
table of :func:`lorentz_gas.load`, and the result objects of the outputs no Python call makes
(speed against error, observer costs, a sweep's part, a figure's data, Slurm scripts)."""

from __future__ import annotations

from typing import Any, Callable, Dict, List, Optional, Tuple

import numpy as np

from . import _cycles, _tables
from ._result_base import Result
from ._results import (
    AuditResult,
    BackscatterResult,
    BenchResult,
    CertifyResult,
    ConstantsResult,
    DiffusionResult,
    EscapeResult,
    FieldResult,
    FieldSweepResult,
    FigureResult,
    FreePathResult,
    HopsResult,
    LatticeWalkResult,
    LyapunovResult,
    ReportResult,
    ReproduceResult,
    ShadowResult,
    SuperdiffusionResult,
    SweepResult,
    TableDiffusionResult,
    TheoryResult,
    TrajectoryResult,
)
from ._current import CurrentResult, DrivenSweepResult
from ._section import SectionResult


class SpeedErrorResult(Result):
    """Speed against error (``lorentz bench --report``, ``speed-vs-error.json``): ``rows``, one
    record per number type (f64, MPFR at each precision) with its time per collision and the
    error it reaches; ``collisions_for_0_1_percent`` (the collisions D needs for a relative error
    of 0.1 %), from a calibration run of ``calibration_collisions`` with relative error
    ``calibration_relative_err``; ``w``; ``meta``. ``to_pandas()`` gives ``rows``."""

    def __init__(self, text: str):
        super().__init__(text)
        self.rows = _tables.records(self._data["rows"])

    def _summary(self) -> str:
        return (f"{len(self.rows)} number types at w = {self._data.get('w')}, "
                f"{self._data.get('collisions_for_0_1_percent'):.3g} collisions for 0.1 %")


class ObserverCostsResult(Result):
    """What each observer costs (``lorentz bench --observer-costs``): ``costs``, one record per
    observer with ``observe``, ``ns_per_collision`` and ``over_bare`` (its time over the bare
    engine's); ``to_pandas()`` gives ``costs``."""

    def __init__(self, text: str):
        super().__init__(text)
        self.costs = _tables.records(self._data["costs"])

    def _summary(self) -> str:
        return f"{len(self.costs)} observers timed at w = {self._data.get('w')}"


class ShardResult(Result):
    """One part of a sharded sweep (``lorentz sweep --shard I/N``; ``shard.json`` or
    ``field-shard.json`` in its folder, which ``lorentz merge`` reads): the whole sweep's
    ``config``, which part (``shard``: ``index`` of ``count``), its finished ``points`` and how
    many were ``resumed_points``."""

    def _summary(self) -> str:
        s = self._data["shard"]
        return f"part {s.get('index')} of {s.get('count')}: {len(self._data['points'])} points"


class FigureDataResult(Result):
    """The numbers of a figure of the paper (``lorentz figure``'s ``<figure>.json``): ``data``
    (a dict: the figure's parameters, and for a curve its ``rows``) and ``meta``; ``to_pandas()``
    gives the rows where there are some."""

    def _more_tables(self) -> Dict[str, np.ndarray]:
        data = self._data.get("data")
        return _tables.of_data(data) if isinstance(data, dict) else {}

    @property
    def _default_table(self) -> Optional[str]:  # type: ignore[override]
        return "rows" if "rows" in self._more_tables() else None

    def _summary(self) -> str:
        data = self._data.get("data")
        return "figure data: " + ", ".join(data) if isinstance(data, dict) else "figure data"


class SlurmResult(Result):
    """The scripts of a Slurm campaign (``lorentz slurm sweep --json``): ``files`` written and
    the ``submit`` command."""

    def _summary(self) -> str:
        return f"{len(self._data.get('files', []))} files; submit with {self._data.get('submit')}"


#: Every kind of result, in the order they are tried: (name, what writes it, the keys that
#: identify it, its class). The first kind whose keys the file has all of is the file's kind;
#: kinds whose keys contain another's come first.
KINDS: List[Tuple[str, str, Tuple[str, ...], Callable[..., Result]]] = [
    ("table-diffusion", "diffusion --table", ("batch_D", "identities", "table"),
     TableDiffusionResult),
    ("diffusion", "diffusion", ("batch_D", "msd_times"), DiffusionResult),
    ("field", "diffusion --field", ("batch_D_xx", "localized_fraction_exact"), FieldResult),
    ("current", "diffusion --electric", ("J_parallel", "mobility"), CurrentResult),
    ("driven-sweep", "sweep --electric (driven-sweep.json), merge", ("rows", "odd"),
     DrivenSweepResult),
    ("field-sweep", "sweep --fields (field-sweep.json), merge", ("rows", "onsager"),
     FieldSweepResult),
    ("sweep", "sweep (sweep.json), merge", ("rows", "linear_fit"), SweepResult),
    ("speed-vs-error", "bench --report (speed-vs-error.json)",
     ("rows", "collisions_for_0_1_percent"), SpeedErrorResult),
    ("bench-long-flights", "bench --long-flights", ("rows", "config"), BenchResult),
    ("bench", "bench", ("collisions_per_second_per_thread", "samples"), BenchResult),
    ("observer-costs", "bench --observer-costs", ("costs", "rounds"), ObserverCostsResult),
    ("hops", "hops", ("pairs", "sequences"), HopsResult),
    ("theory", "theory", ("orders",), TheoryResult),
    ("lattice-walk", "lattice-walk", ("walks",), LatticeWalkResult),
    ("backscatter", "backscatter", ("mean_visit_time",), BackscatterResult),
    ("escape", "escape", ("D_escape",), EscapeResult),
    ("escape-survival", "escape --repeller, escape --open", ("gamma", "windows", "pilot_gamma"),
     _cycles.SurvivalResult),
    ("lyapunov", "lyapunov", ("tangent",), LyapunovResult),
    ("superdiffusion", "superdiffusion", ("lags", "limit_law"), SuperdiffusionResult),
    ("free-paths", "free-paths", ("bins", "ln_mean_limit"), FreePathResult),
    ("audit", "audit", ("events", "quantiles", "summary"), AuditResult),
    ("shadow", "shadow", ("segments", "converged", "certified"), ShadowResult),
    ("certify", "certify", ("digits_agreed", "f64_faithful_collisions"), CertifyResult),
    ("cycles", "cycles", ("spectral_determinant", "zeta_function"), _cycles.CyclesResult),
    ("lattice-cycles", "cycles --w", ("letters", "refused", "mean_free_time_exact"),
     _cycles.LatticeCyclesResult),
    ("trajectory", "trajectory", ("certified_digits", "distance"), TrajectoryResult),
    ("section", "section", ("theta", "p", "component"), SectionResult),
    ("constants", "constants", ("mean_free_path", "finite_horizon", "precision_bits"),
     ConstantsResult),
    ("report", "report (report.json)", ("verdict", "checks", "provenance"), ReportResult),
    ("reproduce", "reproduce (reproduce.json)", ("steps", "budget"), ReproduceResult),
    ("shard", "sweep --shard (shard.json, field-shard.json)", ("shard", "points", "config"),
     ShardResult),
    ("slurm", "slurm sweep", ("files", "submit"), SlurmResult),
    ("figure", "figure", ("files",), FigureResult),
    ("figure-data", "figure (<figure>.json)", ("data", "meta"), FigureDataResult),
]


def kind_of(data: Dict[str, Any]) -> Optional[Tuple[str, Callable[..., Result]]]:
    """The name and class of the first kind whose identifying keys ``data`` has, or ``None``."""
    for name, _, keys, cls in KINDS:
        if all(k in data for k in keys):
            return name, cls
    return None


def listed() -> str:
    """The kinds for a message: ``table-diffusion (batch_D, identities, table), …``."""
    return "; ".join(f"{name} ({', '.join(keys)})" for name, _, keys, _ in KINDS)

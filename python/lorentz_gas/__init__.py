"""Deterministic diffusion in the two-dimensional periodic Lorentz gas.

A point particle of speed 1 among hard disks of radius 1 on a triangular lattice of spacing
2 + w (Klages & Dellago, J. Stat. Phys. 101, 145 (2000)), or among disks of radius r at the
integer points of the plane (the square scene). Every function runs the ``lorentz-gas`` Rust
library and returns what ``lorentz <command> --json`` prints, with the same bits for the same
parameters and seed. Lengths are in units of the disk radius (triangular) or of the lattice
spacing (square); times in those units over the speed 1.

Inputs
    Gaps and radii: a ``str`` (an exact decimal ``"0.1"`` or fraction ``"1/10"``, parsed as the
    command line parses it), a ``fractions.Fraction`` or ``decimal.Decimal`` (exact), or a
    ``float`` (taken as its shortest decimal, ``0.1`` as ``"0.1"``). Counts: an ``int``, a
    whole ``float`` (``2e9``) or a string (``"2e9"``, ``"2_000_000_000"``).

Behaviour
    The GIL is released while computing; Ctrl-C (``KeyboardInterrupt``) stops a run within
    about a second (certify, trajectory, shadow and report finish first) and leaves no thread
    behind; ``progress=True`` shows a tqdm bar when tqdm is
    installed (or pass a callable receiving the units done since its last call). Bad input
    raises ``ValueError`` with the command line's one-line message naming the valid range; I/O
    problems raise ``OSError`` naming the path.

Example
    >>> import lorentz_gas as lg
    >>> r = lg.diffusion(w=0.1, collisions=2e7, batches=8)   # doctest: +SKIP
    >>> r                                                     # doctest: +SKIP
    <DiffusionResult: D = 0.0998... ± 0.000... at w = 0.1>
"""

from __future__ import annotations

import numpy as np  # noqa: F401  (the namespace of the package's doctests, `doctest.testmod`)

from . import _native
from ._native import CheckFailedError, ComputationError
from ._current import CurrentResult, DrivenSweepResult
from ._results import (
    AuditResult,
    BackscatterResult,
    BenchResult,
    CertifyResult,
    ConstantsResult,
    ConstantsTable,
    DiffusionResult,
    EscapeResult,
    FieldResult,
    FigureResult,
    FreePathResult,
    HopsResult,
    LatticeWalkResult,
    LyapunovResult,
    ReportResult,
    ReproduceResult,
    Result,
    ShadowResult,
    SuperdiffusionResult,
    SweepResult,
    FieldSweepResult,
    TableDiffusionResult,
    TheoryResult,
    TrajectoryResult,
)

from ._drawing import ARC_DTYPE, arcs, draw_events, draw_lattice, lattice_disks

# The functions and classes below are defined in private modules; each is the package's own
# (`__module__` "lorentz_gas": `help`, reprs, Sphinx and the doctests name it `lorentz_gas.<name>`),
# and every function refuses a misspelt keyword by naming the one meant (`_keywords.public`).
from ._inputs import agreement_bound
from ._inputs import Count, Exact, PathLike, Progress  # noqa: F401  (the types of the inputs)
from ._progress import _in_notebook  # noqa: F401  (the switch of the default bar: `_progress._Bar`)
from ._transport import (
    backscatter,
    diffusion,
    escape,
    hops,
    lattice_walk,
    superdiffusion,
    theory,
)
from ._sweep import ShardResult, merge, sweep
from ._bench import bench
from ._verification import (
    audit,
    certify,
    constants,
    free_paths,
    lyapunov,
    report,
    shadow,
    trajectory,
)
from ._figures import figure, reproduce
from ._section import SectionResult, section
from ._cycles import CyclesResult, LatticeCyclesResult, SurvivalResult, cycles
from ._events import Trajectory, events
from . import _events
from ._kinds import (
    FigureDataResult,
    ObserverCostsResult,
    ShardResult,
    SlurmResult,
    SpeedErrorResult,
)
from ._load import load

# Restated here: Sphinx reads the doc comment of a name of the package in this file.
#: The dtype of :func:`events`: one record per event.
EVENT_DTYPE = _events.EVENT_DTYPE

__version__ = _native.__version__

__all__ = [
    "diffusion",
    "hops",
    "theory",
    "lattice_walk",
    "backscatter",
    "sweep",
    "merge",
    "escape",
    "lyapunov",
    "superdiffusion",
    "free_paths",
    "audit",
    "shadow",
    "certify",
    "cycles",
    "trajectory",
    "section",
    "constants",
    "report",
    "load",
    "figure",
    "reproduce",
    "events",
    "bench",
    "Trajectory",
    "draw_lattice",
    "lattice_disks",
    "arcs",
    "draw_events",
    "EVENT_DTYPE",
    "ARC_DTYPE",
    "agreement_bound",
    "Result",
    "ConstantsResult",
    "ConstantsTable",
    "DiffusionResult",
    "TableDiffusionResult",
    "FieldResult",
    "CurrentResult",
    "DrivenSweepResult",
    "HopsResult",
    "TheoryResult",
    "LatticeWalkResult",
    "BackscatterResult",
    "SuperdiffusionResult",
    "SweepResult",
    "FieldSweepResult",
    "ShardResult",
    "EscapeResult",
    "LyapunovResult",
    "FreePathResult",
    "AuditResult",
    "ShadowResult",
    "CertifyResult",
    "CyclesResult",
    "LatticeCyclesResult",
    "SurvivalResult",
    "TrajectoryResult",
    "SectionResult",
    "BenchResult",
    "ReportResult",
    "FigureResult",
    "ReproduceResult",
    "SpeedErrorResult",
    "ObserverCostsResult",
    "ShardResult",
    "FigureDataResult",
    "SlurmResult",
    "CheckFailedError",
    "ComputationError",
]

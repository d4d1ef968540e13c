"""Type stubs of the compiled module (`python/src/`). Call the keyword functions of
`lorentz_gas` instead: each analysis here takes one dict of the keyword function's parameters
(every value as the text the command line parses; a key it does not read is refused) and the
progress callback, and returns the command line's JSON. `parameters(name)` names the keys an
analysis reads; each TypedDict below lists them."""

from typing import Callable, Dict, List, Optional, Tuple, TypedDict

import numpy as np

__version__: str
BYTES_PER_EVENT: int

class CheckFailedError(RuntimeError): ...
class ComputationError(RuntimeError): ...

Progress = Optional[Callable[[int], object]]

class DiffusionParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    rel_err: Optional[float]
    plan_only: bool
    collisions: Optional[str]
    batches: str
    seed: str
    precision: str
    window: Tuple[float, float]
    check_window: Tuple[float, float]
    msd_grid: str
    localization_samples: str
    field: Optional[str]
    electric: Optional[str]
    electric_angle: str
    audit: Optional[float]
    reference_bits: str
    threads: Optional[str]
    engine: str
    checkpoint: Optional[str]
    checkpoint_every: float

class HopParams(TypedDict):
    w: str
    collisions: str
    batches: str
    order: str
    seed: str
    threads: Optional[str]
    checkpoint: Optional[str]
    checkpoint_every: float

class HopsParams(HopParams):
    engine: str

class BackscatterParams(TypedDict):
    w: str
    particles: str
    batches: str
    seed: str
    threads: Optional[str]
    precision: str

class SweepParams(TypedDict):
    w_from: str
    w_to: str
    steps: str
    runs: str
    collisions_per_run: str
    batches_per_run: str
    seed: str
    threads: Optional[str]
    engine: str
    out: Optional[str]
    shard: Optional[str]
    checkpoint_every: float

class FieldSweepParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    w_from: Optional[str]
    w_to: Optional[str]
    steps: str
    field: Optional[str]
    fields: List[str]
    collisions_per_run: str
    batches_per_run: str
    seed: str
    localization_samples: str
    shard: Optional[str]
    threads: Optional[str]
    engine: str
    out: Optional[str]

class DrivenSweepParams(TypedDict):
    w: str
    electric: List[str]
    electric_angle: str
    collisions_per_run: str
    batches_per_run: str
    seed: str
    shard: Optional[str]
    threads: Optional[str]
    engine: str
    out: Optional[str]

class MergeParams(TypedDict):
    shards: List[str]
    out: Optional[str]
    threads: Optional[str]

class EscapeParams(TypedDict):
    w: str
    widths: Optional[List[float]]
    particles_per_width: str
    seed: str
    threads: Optional[str]
    checkpoint: Optional[str]
    checkpoint_every: float

class SuperdiffusionParams(TypedDict):
    scene: str
    w: Optional[str]
    radius: Optional[str]
    collisions: str
    batches: str
    octaves: str
    points_per_octave: str
    tail_fit_from: float
    vacf_fit: Optional[Tuple[float, float]]
    msd_fit: Optional[Tuple[float, float]]
    seed: str
    flights: str
    threads: Optional[str]
    checkpoint: Optional[str]
    checkpoint_every: float

class FreePathsParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    collisions: str
    batches: str
    seed: str
    flights: str
    bins: Optional[str]
    keep_samples: str
    threads: Optional[str]

class ReportParams(TypedDict):
    path: str
    out: Optional[str]
    quick: bool
    reference_bits: str
    max_rerun_collisions: Optional[str]
    threads: Optional[str]

class ConstantsParams(TypedDict):
    w: Optional[str]
    radius: Optional[str]
    precision: str

class SectionParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    field: Optional[str]
    trajectories: str
    collisions: str
    classify_collisions: str
    seed: str
    threads: Optional[str]

class LyapunovParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    collisions_per_batch: str
    batches: str
    starts: Optional[str]
    seed: str
    threads: Optional[str]
    field: Optional[str]
    flights: str
    electric: Optional[str]
    electric_angle: Optional[str]

class AuditParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    collisions: str
    batches: str
    sample: float
    reference_bits: str
    seed: str
    field: Optional[str]
    electric: Optional[str]
    electric_angle: Optional[str]
    flights: str
    threads: Optional[str]

class ShadowParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    collisions_per_segment: str
    segments: str
    reference_bits: str
    seed: str
    field: Optional[str]
    electric: Optional[str]
    electric_angle: Optional[str]
    threads: Optional[str]

class CertifyParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    collisions: str
    digits: str
    seed: str

class CyclesParams(TypedDict):
    side: str
    radius: str
    max_length: str
    bits: str
    threads: Optional[str]

class LatticeCyclesParams(TypedDict):
    w: str
    max_length: str
    bits: str
    msd_collisions: str
    threads: Optional[str]

class SurvivalParams(TypedDict):
    side: str
    radius: str
    open_table: Optional[str]
    particles: str
    window: str
    seed: str
    threads: Optional[str]

class TrajectoryParams(TypedDict):
    scene: str
    w: Optional[str]
    radius: Optional[str]
    start: Tuple[str, str]
    direction: Tuple[str, str]
    time: str
    digits: str
    events: bool
    field: Optional[str]
    electric: Optional[str]
    electric_angle: Optional[str]

class EventStreamParams(TypedDict):
    scene: str
    table: Optional[str]
    w: Optional[str]
    radius: Optional[str]
    seed: str
    batch: str
    field: Optional[str]
    flights: str

class BenchParams(TypedDict):
    w: str
    collisions_per_thread: str
    repetitions: str
    precision: str
    engine: str
    observe: str
    seed: str
    threads: str
    field: Optional[str]
    straight_beside: bool
    oracle_floor: bool
    diffusion_beside: bool
    table: Optional[str]
    electric: Optional[str]
    electric_angle: Optional[str]

class BenchLongFlightsParams(TypedDict):
    scene: str
    long_flights: List[str]
    collisions_per_radius: str
    walk_collisions: str
    repetitions: str
    seed: str

class FigureParams(TypedDict):
    kind: str
    w: Optional[str]
    particles: Optional[str]
    particles_per_gap: Optional[str]
    collisions_per_gap: Optional[str]
    seed: str
    threads: Optional[str]
    out: str

class ReproduceParams(TypedDict):
    budget: str
    seed: str
    threads: Optional[str]
    out: str

def diffusion(params: DiffusionParams, progress: Progress) -> str: ...
def hops(params: HopsParams, progress: Progress) -> str: ...
def theory(params: HopParams, progress: Progress) -> str: ...
def lattice_walk(params: HopParams, progress: Progress) -> str: ...
def backscatter(params: BackscatterParams, progress: Progress) -> str: ...
def sweep(params: SweepParams, progress: Progress) -> str: ...
def field_sweep(params: FieldSweepParams, progress: Progress) -> str: ...
def driven_sweep(params: DrivenSweepParams, progress: Progress) -> str: ...
def merge(params: MergeParams, progress: Progress) -> str: ...
def merge_parts(parts: List[str], out: Optional[str], threads: Optional[str]) -> str: ...
def escape(params: EscapeParams, progress: Progress) -> str: ...
def lyapunov(params: LyapunovParams, progress: Progress) -> str: ...
def superdiffusion(params: SuperdiffusionParams, progress: Progress) -> str: ...
def free_paths(params: FreePathsParams, progress: Progress) -> str: ...
def audit(params: AuditParams, progress: Progress) -> str: ...
def shadow(params: ShadowParams, progress: Progress) -> str: ...
def certify(params: CertifyParams, progress: Progress) -> str: ...
def cycles(params: CyclesParams, progress: Progress) -> str: ...
def lattice_cycles(params: LatticeCyclesParams, progress: Progress) -> str: ...
def survival(params: SurvivalParams, progress: Progress) -> str: ...
def trajectory(params: TrajectoryParams, progress: Progress) -> Tuple[str, str]: ...
def section(params: SectionParams, progress: Progress) -> str: ...
def report(params: ReportParams, progress: Progress) -> Tuple[str, str]: ...
def constants(params: ConstantsParams) -> Tuple[str, str]: ...
def parameters(name: str) -> List[str]: ...
def agreement_bound(dof: float) -> float: ...
class EventStream:
    def __init__(self, params: EventStreamParams) -> None: ...
    def start(self) -> Dict[str, np.ndarray]: ...
    def next(self, n: str, progress: Progress) -> Dict[str, np.ndarray]: ...
    @property
    def time(self) -> float: ...
    @property
    def flights(self) -> str: ...
def bench(params: BenchParams, progress: Progress) -> str: ...
def bench_long_flights(params: BenchLongFlightsParams, progress: Progress) -> str: ...
def collisions_for(collisions: int, batches: int, achieved: float, target: float) -> int: ...
def figure(params: FigureParams, progress: Progress) -> Tuple[str, str]: ...
def reproduce(params: ReproduceParams, progress: Progress) -> Tuple[str, str]: ...
def text(kind: str, json: str) -> Optional[str]: ...
def read_table(path: str) -> str: ...

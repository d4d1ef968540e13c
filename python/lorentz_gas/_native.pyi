"""Type stubs of the compiled module (`python/src/`). Call the keyword functions of
`lorentz_gas` instead: these take every value as the text the command line parses and return
the command line's JSON."""

from typing import Callable, Dict, List, Optional, Tuple

import numpy as np

__version__: str
BYTES_PER_EVENT: int

class CheckFailedError(RuntimeError): ...
class ComputationError(RuntimeError): ...

Progress = Optional[Callable[[int], object]]

def diffusion(
    scene: str, w: Optional[str], radius: Optional[str], collisions: Optional[str], batches: str, seed: str, threads: Optional[str],
    engine: str, precision: str, window: Tuple[float, float], check_window: Tuple[float, float],
    checkpoint: Optional[str], checkpoint_every: float, audit: Optional[float],
    reference_bits: str, field: Optional[str], localization_samples: str, progress: Progress,
    rel_err: Optional[float], msd_grid: str = ...,
) -> str: ...
def hops(
    w: str, collisions: str, batches: str, order: str, seed: str, threads: Optional[str],
    engine: str, checkpoint: Optional[str], checkpoint_every: float, progress: Progress,
) -> str: ...
def theory(
    w: str, collisions: str, batches: str, order: str, seed: str, threads: Optional[str],
    checkpoint: Optional[str], checkpoint_every: float, progress: Progress,
) -> str: ...
def lattice_walk(
    w: str, collisions: str, batches: str, order: str, seed: str, threads: Optional[str],
    checkpoint: Optional[str], checkpoint_every: float, progress: Progress,
) -> str: ...
def backscatter(
    w: str, particles: str, batches: str, seed: str, threads: Optional[str], precision: str,
    progress: Progress,
) -> str: ...
def sweep(
    w_from: str, w_to: str, steps: str, runs: str, collisions_per_run: str,
    batches_per_run: str, seed: str, threads: Optional[str], engine: str, out: Optional[str],
    checkpoint_every: float, progress: Progress,
) -> str: ...
def field_sweep(
    scene: str, w: Optional[str], radius: Optional[str], w_from: Optional[str], w_to: Optional[str], steps: str,
    field: Optional[str], fields: List[str], collisions_per_run: str, batches_per_run: str,
    seed: str, threads: Optional[str], engine: str, localization_samples: str,
    out: Optional[str], progress: Progress,
) -> str: ...
def escape(
    w: str, widths: Optional[List[float]], particles_per_width: str, seed: str,
    threads: Optional[str], checkpoint: Optional[str], checkpoint_every: float,
    progress: Progress,
) -> str: ...
def lyapunov(
    scene: str, w: Optional[str], radius: Optional[str], collisions_per_batch: str,
    batches: str, starts: Optional[str], seed: str, threads: Optional[str], field: Optional[str],
    flights: str, progress: Progress,
) -> str: ...
def superdiffusion(
    scene: str, w: Optional[str], radius: Optional[str], collisions: str, batches: str,
    octaves: str, points_per_octave: str, tail_fit_from: float,
    vacf_fit: Optional[Tuple[float, float]], msd_fit: Optional[Tuple[float, float]], seed: str, flights: str,
    threads: Optional[str], checkpoint: Optional[str],
    checkpoint_every: float, progress: Progress,
) -> str: ...
def free_paths(
    scene: str, w: Optional[str], radius: Optional[str], collisions: str, batches: str,
    seed: str, flights: str, threads: Optional[str], progress: Progress,
) -> str: ...
def audit(
    scene: str, w: Optional[str], radius: Optional[str], collisions: str, batches: str,
    sample: float, reference_bits: str, seed: str, field: Optional[str], flights: str, threads: Optional[str],
    progress: Progress,
) -> str: ...
def shadow(
    scene: str, w: Optional[str], radius: Optional[str], collisions_per_segment: str, segments: str, reference_bits: str, seed: str,
    field: Optional[str], threads: Optional[str], progress: Progress,
) -> str: ...
def certify(
    scene: str, w: Optional[str], radius: Optional[str], collisions: str, digits: str,
    seed: str, progress: Progress,
) -> str: ...
def trajectory(
    scene: str, w: Optional[str], radius: Optional[str], start: Tuple[str, str],
    direction: Tuple[str, str], time: str, digits: str, events: bool, field: Optional[str],
    progress: Progress,
) -> Tuple[str, str]: ...
def report(
    result: str, out: Optional[str], quick: bool, reference_bits: str,
    max_rerun_collisions: Optional[str], threads: Optional[str], progress: Progress,
) -> Tuple[str, str]: ...
def constants(w: Optional[str], radius: Optional[str], precision: str) -> Tuple[str, str]: ...
def agreement_bound(dof: float) -> float: ...
class EventStream:
    def __init__(
        self, scene: str, w: Optional[str], radius: Optional[str], seed: str, batch: str,
        field: Optional[str], flights: str,
    ) -> None: ...
    def start(self) -> Dict[str, np.ndarray]: ...
    def next(self, n: str, progress: Progress) -> Dict[str, np.ndarray]: ...
    @property
    def time(self) -> float: ...
    @property
    def flights(self) -> str: ...
def bench(
    w: str, collisions_per_thread: str, repetitions: str, precision: str, engine: str,
    observe: str, seed: str, threads: str, field: Optional[str], straight_beside: bool,
    oracle_floor: bool, progress: Progress,
) -> str: ...
def bench_long_flights(
    scene: str, values: List[str], collisions_per_radius: str, walk_collisions: str, repetitions: str,
    seed: str, progress: Progress,
) -> str: ...
def collisions_for(collisions: int, batches: int, achieved: float, target: float) -> int: ...
def figure(
    kind: str, w: Optional[str], particles: Optional[str], particles_per_gap: Optional[str],
    collisions_per_gap: Optional[str], seed: str, threads: Optional[str], out: str,
    progress: Progress,
) -> Tuple[str, str]: ...
def reproduce(
    budget: str, seed: str, threads: Optional[str], out: str, progress: Progress,
) -> Tuple[str, str]: ...
def text(kind: str, json: str) -> Optional[str]: ...
def read_table(path: str) -> str: ...

"""The progress of a run: a tqdm bar, or the caller's callable, fed by the compiled run."""

from __future__ import annotations

from typing import Any, Callable, Dict, Optional

from ._inputs import Progress


def _in_notebook() -> bool:
    """Whether the caller runs in a Jupyter kernel (where a bar is wanted by default)."""
    try:
        from IPython import get_ipython
    except ImportError:
        return False
    shell = get_ipython()
    return shell is not None and type(shell).__name__ == "ZMQInteractiveShell"


class _Bar:
    """A tqdm bar fed by the run's progress (nothing when tqdm is missing)."""

    def __init__(self, progress: Progress, total: Optional[float], unit: str):
        self.bar = None
        self.callback: Optional[Callable[[int], Any]] = None
        if progress is None:
            # Looked up on the package at each run, not bound here: ``lorentz_gas._in_notebook``
            # is the one switch (a test, or a front end that knows better, may replace it).
            from . import _in_notebook as in_notebook

            progress = in_notebook()
        if callable(progress):
            self.callback = progress
        elif progress:
            try:
                import ipywidgets  # noqa: F401  (tqdm's notebook bar needs it)
                from tqdm.auto import tqdm
            except ImportError:
                try:
                    from tqdm import tqdm
                except ImportError:
                    return
            self.bar = tqdm(
                total=None if total is None else int(total),
                unit=unit,
                unit_scale=True,
                dynamic_ncols=True,
            )
            self.callback = self.bar.update

    def __enter__(self) -> Optional[Callable[[int], Any]]:
        return self.callback

    def __exit__(self, *exc: Any) -> None:
        if self.bar is not None:
            self.bar.close()


def _run(
    native: Callable[..., Any],
    progress: Progress,
    total: Optional[float],
    unit: str,
    request: Dict[str, Any],
) -> Any:
    """The compiled run ``native(request, callback)``, its progress reported on a bar over
    ``total`` ``unit`` as :class:`_Bar` does."""
    with _Bar(progress, total, unit) as cb:
        return native(request, cb)

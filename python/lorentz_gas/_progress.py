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


class _Feed:
    """What the compiled run calls on a bar: ``feed(n)`` for ``n`` more units done, and
    ``feed.restart(total)`` when a second stage starts (the run a pilot planned): the bar starts
    again over that stage's total, so that its rate and time estimate are the stage's own."""

    def __init__(self, bar: Any):
        self.bar = bar

    def __call__(self, n: int) -> None:
        self.bar.update(n)

    def restart(self, total: int) -> None:
        self.bar.reset(total=int(total))
        self.bar.set_description("planned run")


class _Bar:
    """A tqdm bar fed by the run's progress (nothing when tqdm is missing); ``desc`` names its
    first stage."""

    def __init__(self, progress: Progress, total: Optional[float], unit: str, desc: str = ""):
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
                desc=desc or None,
            )
            self.callback = _Feed(self.bar)

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
    desc: str = "",
) -> Any:
    """The compiled run ``native(request, callback)``, its progress reported on a bar over
    ``total`` ``unit`` as :class:`_Bar` does."""
    with _Bar(progress, total, unit, desc) as cb:
        return native(request, cb)

"""The example notebook `python/examples/quickstart.ipynb` runs end to end with small statistics.

The notebook checks its own results (it raises when D, its error bar or the mean free path
contradict theory), so executing it is a test of the physics as well as of the example. It is run
with nbclient on the Jupyter kernel "python3", which must be this interpreter's ipykernel; if the
kernel is missing, register it with `python -m ipykernel install --sys-prefix`.
"""

import pathlib
import re
import sys

import pytest

NOTEBOOK = pathlib.Path(__file__).resolve().parents[1] / "examples" / "quickstart.ipynb"
KERNEL = "python3"


def _require(module: str):
    """Import a test dependency, failing (not skipping) when it is missing: CI installs them."""
    try:
        return __import__(module)
    except ImportError as e:
        pytest.fail(
            f"the notebook test needs {module!r} ({e}): pip install './python[test]' "
            "(nbclient, nbformat, ipykernel, matplotlib)",
            pytrace=False,
        )


def test_the_quickstart_notebook_runs_with_small_statistics(tmp_path, monkeypatch):
    nbformat = _require("nbformat")
    nbclient = _require("nbclient")
    _require("ipykernel")
    _require("matplotlib")
    from jupyter_client.kernelspec import KernelSpecManager, NoSuchKernel

    try:
        KernelSpecManager().get_kernel_spec(KERNEL)
    except NoSuchKernel:
        pytest.fail(
            f"no Jupyter kernel {KERNEL!r}: register this interpreter's with "
            f"`{sys.executable} -m ipykernel install --sys-prefix`",
            pytrace=False,
        )

    # The kernel inherits this environment: small statistics, and matplotlib's inline backend
    # (not a GUI backend from the environment).
    monkeypatch.setenv("LORENTZ_NOTEBOOK_SMALL", "1")
    monkeypatch.delenv("MPLBACKEND", raising=False)

    nb = nbformat.read(NOTEBOOK, as_version=4)
    client = nbclient.NotebookClient(
        nb,
        kernel_name=KERNEL,
        timeout=600,
        resources={"metadata": {"path": str(tmp_path)}},  # the kernel's working directory
    )
    try:
        client.execute()
    except nbclient.exceptions.CellExecutionError as e:
        # The message names the cell and the exception (for a failed check: what disagreed).
        plain = re.sub(r"\x1b\[[0-9;]*m", "", str(e))  # without the traceback's colours
        pytest.fail(f"{NOTEBOOK.name} failed:\n{plain}", pytrace=False)

    # The small run is really small, and it drew its figures.
    outputs = [o for c in nb.cells if c.cell_type == "code" for o in c.outputs]
    text = "".join(o.get("text", "") for o in outputs if o.output_type == "stream")
    assert "SMALL = True" in text, text
    figures = [o for o in outputs if "image/png" in o.get("data", {})]
    assert len(figures) >= 4, f"expected 4 figures, got {len(figures)}"

"""Shared fixtures: the `lorentz` binary the Python results are compared with."""

import json
import os
import pathlib
import subprocess

import pytest

REPO = pathlib.Path(__file__).resolve().parents[2]


def _binary() -> pathlib.Path:
    env = os.environ.get("LORENTZ_BIN")
    path = pathlib.Path(env) if env else REPO / "target" / "release" / "lorentz"
    if not path.is_file():
        pytest.fail(
            f"the command line binary {path} is missing: build it with `cargo build --release` "
            "(or set LORENTZ_BIN) — these tests compare Python with it"
        )
    return path


@pytest.fixture(scope="session")
def cli():
    """Runs `lorentz ARGS...`; returns (exit status, stdout, stderr)."""
    binary = _binary()

    def run(*args: str):
        p = subprocess.run([str(binary), *args], capture_output=True, text=True, timeout=600)
        return p.returncode, p.stdout, p.stderr

    return run


@pytest.fixture(scope="session")
def cli_json(cli):
    """Runs `lorentz ARGS... --json --quiet` and returns the parsed result."""

    def run(*args: str):
        code, out, err = cli(*args, "--json", "--quiet")
        assert code == 0, err
        return json.loads(out)

    return run

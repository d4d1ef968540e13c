"""Result files in and out: :func:`load` reads any result the command line (or ``save``) wrote
into its result object; :func:`write_new` writes one without following a link or overwriting
another file.

A file is untrusted input: it is read as JSON text only (at most 64 MiB, the command line's cap on
a result file; a key given twice, NaN or Infinity refused, as the command line refuses them),
never executed or unpickled, and recognised by the keys that only its kind writes."""

from __future__ import annotations

import json
import os
import secrets
import stat
from typing import Any, Dict, List, Tuple

from ._inputs import PathLike
from ._keywords import public
from ._result_base import Result

#: The largest result file read: the command line's cap (``crate::files::Cap::RESULT``).
MAX_RESULT_BYTES = 64 << 20


def _unique(pairs: List[Tuple[str, Any]]) -> Dict[str, Any]:
    seen: Dict[str, Any] = {}
    for k, v in pairs:
        if k in seen:
            raise ValueError(f"the key {k!r} is given twice")
        seen[k] = v
    return seen


def _no_constant(name: str) -> Any:
    raise ValueError(f"{name} is not JSON (lorentz writes a value it cannot state as null)")


#: The result files the command line writes into an output folder, which ``load(folder)`` finds.
FOLDER_FILES = ("sweep.json", "field-sweep.json", "driven-sweep.json", "report.json",
                "reproduce.json", "speed-vs-error.json", "shard.json", "field-shard.json",
                "driven-shard.json")


def _in_folder(folder: str) -> str:
    """The one result file of an output folder."""
    found = [f for f in FOLDER_FILES if os.path.isfile(os.path.join(folder, f))]
    if len(found) != 1:
        raise ValueError(
            f"{folder}: a folder with {'none' if not found else ' and '.join(found)} of the "
            f"result files an output folder holds ({', '.join(FOLDER_FILES)}): give the file"
        )
    return os.path.join(folder, found[0])


def _read(path: str) -> str:
    """The text of the regular file ``path`` (at most :data:`MAX_RESULT_BYTES`)."""
    # Opened without blocking (a named pipe is refused below, not waited on).
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_NONBLOCK", 0))
    info = os.fstat(fd)
    if not stat.S_ISREG(info.st_mode):
        os.close(fd)
        raise ValueError(f"{path}: not a regular file, so not a result file")
    if info.st_size > MAX_RESULT_BYTES:
        os.close(fd)
        raise ValueError(f"{path}: {info.st_size} bytes, more than a result file's "
                         f"{MAX_RESULT_BYTES} (64 MiB)")
    with os.fdopen(fd, "rb") as f:
        data = f.read(MAX_RESULT_BYTES + 1)
    if len(data) > MAX_RESULT_BYTES:
        raise ValueError(f"{path}: more than a result file's {MAX_RESULT_BYTES} bytes (64 MiB)")
    try:
        return data.decode("utf-8")
    except UnicodeDecodeError as e:
        raise ValueError(f"{path}: not UTF-8 text, so not a result of lorentz ({e})") from None


@public
def load(path: PathLike) -> Result:
    """The result in the file ``path``, as the result object of its kind: what ``lorentz
    <command> --json`` printed (or wrote into its output folder: ``sweep.json``,
    ``field-sweep.json``, ``report.json``, ``reproduce.json``, ``speed-vs-error.json``,
    ``shard.json``, a figure's JSON; given the folder, its one such file), or what a result's
    ``save`` wrote — a
    :class:`DiffusionResult` for a diffusion, a :class:`SweepResult` for a sweep, and so on.
    ``to_json()`` of the loaded result is the file's text (without its final newline), so
    ``save`` writes the same bytes back.

    The file is read as JSON only, never run: at most 64 MiB, a key given twice refused. A file
    that is not JSON, not an object or not of any kind raises ``ValueError`` naming the path
    (and the kinds known, each with the keys that identify it); a missing or unreadable file
    raises ``OSError`` naming it."""
    from . import _kinds

    file = os.fspath(path)
    if os.path.isdir(file):
        file = _in_folder(file)
    text = _read(file)
    try:
        data = json.loads(text, object_pairs_hook=_unique, parse_constant=_no_constant)
    except (ValueError, RecursionError) as e:
        raise ValueError(f"{file}: not a JSON result of lorentz ({e})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{file}: not a JSON object, so not a result of lorentz")
    found = _kinds.kind_of(data)
    if found is None:
        raise ValueError(
            f"{file}: not a result of lorentz: it has none of the keys that identify the kinds "
            f"known: {_kinds.listed()}"
        )
    name, cls = found
    text = text[:-1] if text.endswith("\n") else text
    try:
        if cls in (_kinds.FigureResult, _kinds.ReproduceResult):
            return cls(text, os.path.dirname(file) or ".")
        return cls(text)
    except Exception as e:  # noqa: BLE001 - untrusted input: whatever fails, the file is at fault
        raise ValueError(
            f"{file}: a malformed {name} result ({type(e).__name__}: {e}); give a file lorentz "
            "wrote"
        ) from None


def write_new(path: PathLike, text: str) -> str:
    """Writes ``text`` to ``path`` (a temporary file beside it, then renamed): a link there is
    refused, and so is a file holding other text (nothing is overwritten). Returns the path."""
    file = os.fspath(path)
    if os.path.islink(file):
        raise ValueError(f"{file}: not a regular file but a link, never written through: give "
                         "another path")
    if os.path.lexists(file):
        if not os.path.isfile(file):
            raise ValueError(f"{file}: not a regular file: give another path")
        with open(file, encoding="utf-8", errors="replace") as f:
            same = f.read() == text
        if same:
            return file
        raise ValueError(f"{file} holds another result (or other text): give another path "
                         "(nothing is overwritten)")
    folder = os.path.dirname(os.path.abspath(file))
    tmp = os.path.join(folder, f".{os.path.basename(file)}.{secrets.token_hex(6)}.tmp")
    # Created new (never an existing file or a link), with the permissions the umask gives.
    fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_NOFOLLOW", 0), 0o666)
    try:
        with os.fdopen(fd, "w", encoding="utf-8", newline="") as f:
            f.write(text)
        os.replace(tmp, file)
    except BaseException:
        os.unlink(tmp)
        raise
    return file

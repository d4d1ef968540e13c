"""Every code block of the documentation (README.md and docs/) runs, and says what it prints.

The convention the pages follow:

* ``python`` blocks run, a page's blocks in order in one namespace (as in a notebook), with
  matplotlib drawing off screen; a block that raises fails the test.
* ``console`` blocks run: each ``$ lorentz ...`` line is the command line binary (the one the
  other tests compare with), in a fresh directory holding ``examples/tables/``, which must exit 0 unless the block's next line says
  ``(exit N)``; every line shown after it must be a line of the real output (stdout or
  stderr), character for character, where ``…`` stands for any text (a wall time, a rate, digits
  left out) — same seed, same bits, so an example whose numbers went stale fails here.
* ``sh`` blocks are installation commands and runs too long for a test (an hour-long sweep, a
  fuzz campaign); ``rust`` blocks are the library's examples, run as doctests in ``cargo test``
  where they appear in the crate's documentation; ``text`` blocks are output only. A block in
  any other language fails the test, so that none is left unchecked by accident.
* ``toml`` blocks are table files (``--table FILE``): each is read as one and must be the table
  of a file in ``examples/tables/`` (the one the pages' commands run).
"""

import os
import pathlib
import re
import shlex
import shutil
import subprocess

import pytest

from conftest import REPO, _binary

PAGES = sorted([REPO / "README.md", *(REPO / "docs").rglob("*.md")])
FENCE = re.compile(r"^```([^\n`]*)\n(.*?)^```[ \t]*$", re.S | re.M)
SHOWN_ONLY = {"sh", "rust", "text", ""}


def blocks(page: pathlib.Path):
    """(language, body) of every fenced block of `page`, directives (``{toctree}``) left out."""
    for m in FENCE.finditer(page.read_text(encoding="utf-8")):
        lang = m.group(1).strip()
        if not lang.startswith("{"):
            yield lang, m.group(2)


def test_every_block_has_a_language_the_convention_knows():
    unknown = [
        f"{p.relative_to(REPO)}: ```{lang}"
        for p in PAGES
        for lang, _ in blocks(p)
        if lang not in SHOWN_ONLY | {"python", "console", "toml"}
    ]
    assert not unknown, unknown


def test_toml_blocks_are_the_example_tables(tmp_path):
    from lorentz_gas import _native

    examples = {_native.read_table(str(p)) for p in (REPO / "examples" / "tables").glob("*.toml")}
    shown = [body for p in PAGES for lang, body in blocks(p) if lang == "toml"]
    assert shown, "no toml block"
    for k, body in enumerate(shown):
        path = tmp_path / f"block{k}.toml"
        path.write_text(body, encoding="utf-8")
        assert _native.read_table(str(path)) in examples, body


def test_the_pages_have_blocks_that_run():
    langs = [lang for p in PAGES for lang, _ in blocks(p)]
    assert langs.count("python") >= 2 and langs.count("console") >= 5, langs


@pytest.mark.parametrize(
    "page",
    [p for p in PAGES if any(lang == "python" for lang, _ in blocks(p))],
    ids=lambda p: str(p.relative_to(REPO)),
)
def test_python_blocks_run(page, tmp_path, monkeypatch):
    import matplotlib

    matplotlib.use("Agg")
    monkeypatch.chdir(tmp_path)
    namespace = {"__name__": "__docs__"}
    for lang, body in blocks(page):
        if lang == "python":
            exec(compile(body, f"{page.name} (python block)", "exec"), namespace)


def console_commands(body: str):
    """(command, expected status, shown lines) of each ``$`` line of a console block."""
    out, cmd = [], None
    for line in body.splitlines():
        if line.startswith("$ "):
            cmd = [line[2:], 0, []]
            out.append(cmd)
        elif cmd is not None:
            m = re.fullmatch(r"\(exit (\d+)\)", line.strip())
            if m:
                cmd[1] = int(m.group(1))
            else:
                cmd[2].append(line)
    return out


def shown_as(line: str) -> "re.Pattern[str]":
    """A shown output line as a pattern: exact, with ``…`` for any text."""
    return re.compile(".*".join(re.escape(part) for part in line.split("…")))


CONSOLE = [
    (p, i, c)
    for p in PAGES
    for i, (lang, body) in enumerate(blocks(p))
    if lang == "console"
    for c in console_commands(body)
]


@pytest.mark.parametrize(
    "page,block,command",
    CONSOLE,
    ids=[f"{p.relative_to(REPO)}#{i}:{c[0][:60]}" for p, i, c in CONSOLE],
)
def test_console_blocks_print_what_they_show(page, block, command, tmp_path):
    line, status, shown = command
    args = shlex.split(line)
    assert args[0] == "lorentz", f"{page.name}: a console block runs `lorentz`, not {args[0]}"
    # The commands run in a fresh directory that holds the repository's example tables, as a
    # reader's checkout does.
    shutil.copytree(REPO / "examples" / "tables", tmp_path / "examples" / "tables")
    p = subprocess.run(
        [str(_binary()), *args[1:]],
        capture_output=True,
        text=True,
        timeout=300,
        cwd=tmp_path,
        env={**os.environ, "NO_COLOR": "1"},
    )
    assert p.returncode == status, f"`{line}` exited {p.returncode}: {p.stderr}"
    printed = (p.stdout + p.stderr).splitlines()
    stale = [
        s for s in shown if s.strip() and not any(shown_as(s.rstrip()).fullmatch(o.rstrip()) for o in printed)
    ]
    assert not stale, (
        f"{page.relative_to(REPO)}: `{line}` no longer prints\n  "
        + "\n  ".join(stale)
        + "\nit prints:\n"
        + p.stdout
    )

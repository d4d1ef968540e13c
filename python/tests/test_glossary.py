"""One vocabulary: every word of every name a user types or reads is defined in the glossary.

The names are the long options of every ``lorentz`` command and the command names (read from the
binary's ``--help``, the one the other tests compare with), the keywords of the public Python API
(``lorentz_gas.__all__``, from the installed package: functions, classes, their public methods,
the fields of ``EVENT_DTYPE``) and the keys of the result files (the tables of
``docs/reference/results.md``). Each name is split into words at ``-`` and ``_`` and read left to
right, longest glossary term first (``D_green_kubo`` is ``D`` + ``green_kubo``); each word must be
a term or a symbol of ``docs/reference/glossary.md``, and none may be a synonym the glossary
refuses ("not: …"). Everything the check allows is on that page, none of it here.

Breaking it on purpose: deleting the row of ``collision`` from the glossary fails with, among
others, "--collisions-per-batch (option of `lorentz lyapunov`): `collisions` is not a term of
docs/reference/glossary.md".
"""

import collections
import inspect
import re
import subprocess

import pytest

from conftest import REPO, _binary

GLOSSARY = REPO / "docs" / "reference" / "glossary.md"
RESULTS = REPO / "docs" / "reference" / "results.md"
#: The first header cell of the tables that define words: terms and symbols.
DEFINING = ("term", "symbol")


def cells(line: str):
    """The cells of a Markdown table row (a ``\\|`` inside a cell is not a separator)."""
    return [c.strip() for c in re.split(r"(?<!\\)\|", line.strip())[1:-1]]


def ticked(text: str):
    return re.findall(r"`([^`]*)`", text)


class Glossary:
    """The terms and symbols of the glossary page, and the synonyms it refuses."""

    def __init__(self, text: str):
        self.terms = {}  # word -> the section it is defined in
        self.refused = {}  # word -> the term that refuses it
        self.problems = []
        section, defining = "", False
        for n, line in enumerate(text.splitlines(), 1):
            if line.startswith("#"):
                section, defining = line.lstrip("# ").strip(), False
                continue
            if not line.startswith("|"):
                defining = False
                continue
            row = cells(line)
            if row and row[0] in DEFINING:
                defining = True
                continue
            if not defining or set("".join(row)) <= set("-: "):
                continue
            words = ticked(row[0])
            if not words or len(row) < 3 or not row[1]:
                self.problems.append(f"glossary line {n}: a row needs terms and a meaning: {line}")
                continue
            for w in words:
                if w in self.terms:
                    self.problems.append(f"glossary line {n}: `{w}` is defined twice")
                self.terms[w] = section
            last = row[-1]
            if last.startswith("not:"):
                for r in last[len("not:") :].split(","):
                    r = r.strip().strip("`")
                    if r:
                        self.refused[r] = words[0]
        for r, term in self.refused.items():
            if r in self.terms:
                self.problems.append(f"`{r}` is refused (under `{term}`) and defined as a term")

    def split(self, name: str):
        """The words of `name`, longest term first; unknown words are returned as (word, False)."""
        parts = [p for p in re.split(r"[-_]", name) if p]
        out, i = [], 0
        while i < len(parts):
            for j in range(len(parts), i, -1):
                word = "_".join(parts[i:j])
                if word in self.terms:
                    out.append((word, True))
                    i = j
                    break
            else:
                out.append((parts[i], False))
                i += 1
        return out


@pytest.fixture(scope="module")
def glossary():
    return Glossary(GLOSSARY.read_text(encoding="utf-8"))


# --- The names --------------------------------------------------------------------------------


def _help(path):
    p = subprocess.run(
        [str(_binary()), *path, "--help"], capture_output=True, text=True, timeout=60
    )
    assert p.returncode == 0, p.stderr
    return p.stdout


def _subcommands(text: str):
    m = re.search(r"^Commands:\n(.*?)(?:\n\S|\Z)", text, re.S | re.M)
    if not m:
        return []
    names = re.findall(r"^  ([a-z][a-z0-9-]*)\s", m.group(1), re.M)
    return [n for n in names if n != "help"]


def cli_names():
    """(name, where) of every command and every long option of every command."""
    out, todo = [], [[]]
    while todo:
        path = todo.pop(0)
        text = _help(path)
        where = f"option of `lorentz {' '.join(path)}`" if path else "option of `lorentz`"
        # Options are listed as `  -h, --help` or `      --name <VALUE>`; help text is deeper.
        for opt in re.findall(r"^(?:  -\w, |      )--([a-z][a-z0-9-]*)", text, re.M):
            out.append((f"--{opt}", where))
        for sub in _subcommands(text):
            out.append((sub, f"command `lorentz {' '.join(path + [sub])}`"))
            todo.append(path + [sub])
    return out


def python_names():
    """(name, where) of every keyword of the public API and every field of EVENT_DTYPE."""
    import numpy as np

    import lorentz_gas as lg

    out = []

    def keywords(f, where):
        try:
            sig = inspect.signature(f)
        except (TypeError, ValueError):  # a builtin (an exception class) has none
            return
        for p in sig.parameters.values():
            if p.name != "self" and p.kind not in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                out.append((p.name, where))

    for name in lg.__all__:
        obj = getattr(lg, name)
        if isinstance(obj, np.dtype):
            out += [(f, f"field of `lorentz_gas.{name}`") for f in obj.names]
        elif inspect.isclass(obj):
            keywords(obj, f"keyword of `lorentz_gas.{name}()`")
            for m, f in inspect.getmembers(obj, inspect.isfunction):
                if not m.startswith("_"):
                    keywords(f, f"keyword of `lorentz_gas.{name}.{m}()`")
        elif callable(obj):
            keywords(obj, f"keyword of `lorentz_gas.{name}()`")
    return out


def _without_parentheses(s: str) -> str:
    while True:
        t = re.sub(r"\([^()]*\)", "", s)
        if t == s:
            return s
        s = t


def json_names():
    """(name, where) of every key the tables of docs/reference/results.md name: the first column
    of the `meta` table; the backticked identifiers of the second column of "Each result's keys"
    (what is in parentheses inside the backticks is prose, as is a span that is an option, a
    quoted value, a file or a command line) and its bare snake_case identifiers."""
    out, table = [], None
    for line in RESULTS.read_text(encoding="utf-8").splitlines():
        if line.startswith("**The `meta` block**"):
            table = "meta"
        elif line.startswith("**Each result's keys**"):
            table = "results"
        if table is None or not line.startswith("| `"):
            continue
        cols = line.split(" | ")
        if table == "meta":
            spans, where = ticked(cols[0]), "key of the `meta` block in results.md"
        else:
            kind = ticked(cols[0])[0]
            where = f"key of the `{kind}` result in results.md"
            body = " | ".join(cols[1:])
            spans = ticked(body)
            outside = _without_parentheses(re.sub(r"`[^`]*`", "", body))
            spans += re.findall(r"\b[A-Za-z][A-Za-z0-9]*(?:_[A-Za-z0-9]+)+\b", outside)
        for s in spans:
            s = _without_parentheses(s)
            if (
                s.startswith(("--", '"', "lorentz "))
                or "/" in s
                or re.search(r"\.(json|csv|md|html|png|svg)\b", s)
                or s in ("PASS", "FAIL", "SKIP", "INCOMPLETE", "N/A")
            ):
                continue
            for ident in re.findall(r"[A-Za-z_][A-Za-z0-9_]*", s):
                if ident.strip("_"):
                    out.append((ident, where))
    return out


SOURCES = {"command line": cli_names, "Python": python_names, "result files": json_names}


# --- The checks -------------------------------------------------------------------------------


def test_the_glossary_is_consistent(glossary):
    assert len(glossary.terms) > 100, "the glossary's tables were not found"
    assert not glossary.problems, "\n".join(glossary.problems)


def test_the_inventory_finds_the_names_it_should():
    # Guards the parsers: a format change that made them find nothing would pass the checks.
    cli = {n for n, _ in cli_names()}
    assert {"--collisions-per-batch", "--check-window", "--w", "lattice-walk"} <= cli
    assert "backscatter-map" in cli
    py = {n for n, _ in python_names()}
    assert {"collisions_per_run", "check_window", "rel_err", "kind"} <= py
    keys = {n for n, _ in json_names()}
    assert {"D_minus_D_check", "command_line", "particles_per_width", "inv_n", "run_D"} <= keys
    assert not {"PASS", "lorentz", "sweep.csv"} & keys


@pytest.mark.parametrize("source", SOURCES)
def test_every_word_of_every_name_is_a_glossary_term(glossary, source):
    unknown = collections.defaultdict(set)
    for name, where in SOURCES[source]():
        for word, known in glossary.split(name):
            if not known:
                unknown[(name, word)].add(where)
    lines = [
        f"{name} ({'; '.join(sorted(where))}): `{word}` is not a term of "
        f"docs/reference/glossary.md"
        for (name, word), where in sorted(unknown.items())
    ]
    assert not lines, f"{len(lines)} name(s) with a word outside the glossary:\n" + "\n".join(lines)


@pytest.mark.parametrize("source", SOURCES)
def test_no_name_uses_a_refused_synonym(glossary, source):
    found = collections.defaultdict(set)
    for name, where in SOURCES[source]():
        for word, _ in glossary.split(name):
            if word in glossary.refused:
                found[(name, word)].add(where)
    lines = [
        f"{name} ({'; '.join(sorted(where))}): `{word}` is a synonym the glossary refuses "
        f"(under `{glossary.refused[word]}`)"
        for (name, word), where in sorted(found.items())
    ]
    assert not lines, "\n".join(lines)

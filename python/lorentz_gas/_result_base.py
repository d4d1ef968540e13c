"""The result object every analysis returns: the command line's JSON as attributes, numeric
lists as numpy arrays, its tables, its text."""

from __future__ import annotations

import copy
import json
from typing import Any, Dict, List, Optional

import numpy as np

from . import _tables


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _array(v: Any) -> Any:
    """A list of numbers (or a rectangular list of such lists) as a numpy array, else ``v``."""
    if isinstance(v, list) and v:
        if all(_is_number(x) for x in v):
            if all(isinstance(x, int) for x in v):
                return np.asarray(v, dtype=np.int64)
            return np.asarray(v, dtype=np.float64)
        if all(isinstance(x, list) and x and all(_is_number(y) for y in x) for x in v):
            if len({len(x) for x in v}) == 1:
                return np.asarray(v, dtype=np.float64)
    return v


def _pm(x: Optional[float], err: Optional[float]) -> str:
    if x is None or err is None:
        return "n/a"
    return f"{x:.6f} ± {err:.6f}"


def _with_error(x: float, err: float) -> str:
    """``x ± err`` with the error to two significant digits and the value to the same decimal
    place (``0.15229 ± 0.00011``), as ``lorentz report``'s headline writes it."""
    import math

    if not (math.isfinite(x) and math.isfinite(err) and err > 0):
        return f"{x} ± {err}"
    place = math.floor(math.log10(err)) - 1
    if not -6 <= place <= 6 or abs(x) >= 1e6:
        return f"{x:.4e} ± {err:.1e}"
    decimals = max(-place, 0)
    return f"{x:.{decimals}f} ± {err:.{decimals}f}"


def _scalars(data: Dict[str, Any]) -> List[tuple]:
    """(key, text) for the result's top-level scalars, each estimate with its ``_err`` as one
    ``x ± err`` entry (the ``_err`` key itself not repeated)."""
    out = []
    for k, v in data.items():
        if k.endswith("_err") and k[: -len("_err")] in data:
            continue
        err = data.get(f"{k}_err")
        if _is_number(v) and _is_number(err):
            out.append((k, _with_error(float(v), float(err))))
        elif _is_number(v) or isinstance(v, (str, bool)):
            out.append((k, str(v)))
    return out


class Result:
    """A result: every key of the command line's ``--json`` output as an attribute (numeric
    lists as numpy arrays), ``meta`` (how it was computed) as a dict, ``to_dict()`` and
    ``to_json()`` (the command line's JSON, digit for digit)."""

    _kind = "result"

    def __init__(self, text: str, *, printed: Optional[str] = None):
        self._json = text
        #: The command line's text of this result, where the call that made it rendered it.
        self._printed = printed
        self._data: Dict[str, Any] = json.loads(text)
        for k, v in self._data.items():
            setattr(self, k, _array(v))

    def keys(self) -> List[str]:
        """The result's keys, in the command line's order."""
        return list(self._data)

    def __getitem__(self, key: str) -> Any:
        return getattr(self, key)

    def to_dict(self) -> Dict[str, Any]:
        """The result as plain Python data (lists, not arrays): ``json.loads(self.to_json())``."""
        return copy.deepcopy(self._data)

    def to_json(self) -> str:
        """The command line's JSON of this result (``lorentz <command> --json``), unchanged."""
        return self._json

    def _summary(self) -> str:
        return ", ".join(self.keys()[:6]) + ", ..."

    def __repr__(self) -> str:
        return f"<{type(self).__name__}: {self._summary()}>"

    def _meta_text(self) -> str:
        m = self._data.get("meta") or {}
        parts = [f"{k} {m[k]}" for k in ("seed", "batches", "precision", "engine", "threads")
                 if m.get(k) is not None]
        return ", ".join(parts)

    #: The result kind whose command-line text the library renders (``None``: not yet).
    _text_kind: Optional[str] = None

    def __str__(self) -> str:
        """The command line's text of this result (``lorentz <command>`` without ``--json``),
        where the library renders it; otherwise the summary line, every scalar of the result
        (estimates as ``x ± err`` to the place of their error) and how it was computed."""
        if self._printed is not None:
            return self._printed.rstrip("\n")
        if self._text_kind is not None:
            from . import _native

            try:
                text = _native.text(self._text_kind, self._json)
            except ValueError:
                # JSON the text cannot be read back from (a value JSON writes as null, such
                # as a NaN): the table below rather than no str() at all.
                text = None
            if text is not None:
                return text.rstrip("\n")
        rows = _scalars(self._data)
        width = max((len(k) for k, _ in rows), default=0)
        lines = [f"{type(self).__name__}: {self._summary()}"]
        lines += [f"  {k:<{width}}  {v}" for k, v in rows]
        if self._meta_text():
            lines.append(f"  ({self._meta_text()})")
        return "\n".join(lines)

    def _repr_html_(self) -> str:
        """The same as a table, for notebooks."""
        import html

        cells = "".join(
            f"<tr><th style='text-align:left'>{html.escape(k)}</th>"
            f"<td style='text-align:left'>{html.escape(v)}</td></tr>"
            for k, v in _scalars(self._data)
        )
        meta = html.escape(self._meta_text())
        return (
            f"<div><b>{html.escape(type(self).__name__)}</b>: {html.escape(self._summary())}"
            f"<table>{cells}</table><small>{meta}</small></div>"
        )

    #: The table ``to_pandas()`` gives without a name (``None``: the result's one structured
    #: array attribute, or with none its scalars).
    _default_table: Optional[str] = None

    def _tables(self) -> Dict[str, np.ndarray]:
        """The result's tables: its numpy structured arrays, by attribute name."""
        return {
            k: v for k, v in vars(self).items()
            if isinstance(v, np.ndarray) and v.dtype.names and not k.startswith("_")
        }

    def _more_tables(self) -> Dict[str, np.ndarray]:
        """Tables of this kind of result beyond its lists of records (its parallel arrays)."""
        return {}

    def _all_tables(self) -> Dict[str, np.ndarray]:
        """Every table: the structured array attributes, each list of records of the JSON (a
        record per entry, nested dicts flattened as ``<key>_<inner>``, lists left out) and the
        kind's own (:meth:`_more_tables`)."""
        tables = {**_tables.of_data(self._data), **self._more_tables(), **self._tables()}
        return {k: v for k, v in tables.items() if v is not None}

    def table_names(self) -> List[str]:
        """The names ``to_pandas(table)`` takes for this result, sorted."""
        return sorted(self._all_tables())

    def to_pandas(self, table: Optional[str] = None):
        """A table of the result as a ``pandas.DataFrame`` (needs pandas): the one named by
        ``table`` (one of :meth:`table_names`: ``rows`` of a sweep, ``lags`` or ``limit_law`` of
        superdiffusion, ``batches`` or ``msd`` of a diffusion, every list of records the JSON
        holds, ...); without ``table``, the result's main table where it has one, or one row
        of its scalars (estimates and their errors as separate columns)."""
        try:
            import pandas as pd
        except ImportError as e:  # pragma: no cover - depends on the environment
            raise ImportError(f"{type(self).__name__}.to_pandas() needs pandas: pip install pandas") from e
        table = table if table is not None else self._default_table
        if table is not None:
            tables = self._all_tables()
            if table not in tables:
                raise ValueError(f"table={table!r}: this result's tables are {sorted(tables) or 'none'}")
            return pd.DataFrame(tables[table])
        tables = self._tables()
        if len(tables) == 1:
            return pd.DataFrame(next(iter(tables.values())))
        if len(tables) > 1:
            raise ValueError(f"this result has several tables: name one with table= ({', '.join(sorted(tables))})")
        return pd.DataFrame([{k: v for k, v in self._data.items()
                              if _is_number(v) or isinstance(v, (str, bool))}])

    def save(self, path: Any) -> str:
        """Writes the result's JSON to the new file ``path`` as ``lorentz <command> --json``
        prints it (the same bytes: ``lorentz report``, ``lorentz merge`` and
        ``lorentz_gas.load`` read it). A file already there is left as it is: one holding these
        bytes is this result, anything else is ``ValueError`` (nothing is overwritten); a link at
        ``path`` is never written through. Returns the path."""
        from ._load import write_new

        return write_new(path, self._json + "\n")

"""A result's tables: its lists of records and its parallel arrays as numpy structured arrays
(one record per row), for ``to_pandas(table)``."""

from __future__ import annotations

from typing import Any, Dict, List, Optional, Sequence

import numpy as np


def _is_number(v: Any) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _column_dtype(values: Sequence[Any]) -> Any:
    """The dtype of one column: text if any entry is text (``None`` as ""), bool if every entry
    is, int64 if every entry is an integer, else float64 (``None`` as NaN)."""
    present = [v for v in values if v is not None]
    if any(isinstance(v, str) for v in present):
        return f"U{max([len(str(v)) for v in present] + [1])}"
    if present and all(isinstance(v, bool) for v in present) and len(present) == len(values):
        return np.bool_
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present) \
            and len(present) == len(values):
        return np.int64
    return np.float64


def _cell(v: Any, dtype: Any) -> Any:
    if v is None:
        return "" if isinstance(dtype, str) else np.nan
    return str(v) if isinstance(dtype, str) else v


def _scalar(v: Any) -> bool:
    return v is None or isinstance(v, (bool, int, float, str))


def flat(record: Dict[str, Any]) -> Dict[str, Any]:
    """A record's scalars, with those of a dict in it as ``<key>_<inner key>`` (one level; lists
    left out: ``d_xx_even: {z: …}`` becomes ``d_xx_even_z``)."""
    out: Dict[str, Any] = {}
    for k, v in record.items():
        if isinstance(v, dict):
            out.update({f"{k}_{i}": x for i, x in v.items() if _scalar(x)})
        elif _scalar(v):
            out[k] = v
    return out


def records(raw: List[Dict[str, Any]]) -> np.ndarray:
    """Records (dicts of scalars; nested dicts flattened, lists left out) as a numpy structured
    array: one field per key of any record, in the first record's order (a key a record lacks
    is NaN or "" there)."""
    rows = [flat(r) for r in raw]
    keys: List[str] = []
    for r in rows:
        keys += [k for k in r if k not in keys]
    dtypes = {k: _column_dtype([r.get(k) for r in rows]) for k in keys}
    return np.array(
        [tuple(_cell(r.get(k), dtypes[k]) for k in keys) for r in rows],
        dtype=[(k, dtypes[k]) for k in keys],
    )


def columns(**arrays: Any) -> Optional[np.ndarray]:
    """Equal-length lists of scalars as one structured array (a column per keyword), or
    ``None`` where any is missing or the lengths differ."""
    lists = {k: v for k, v in arrays.items()}
    if any(not isinstance(v, (list, np.ndarray)) for v in lists.values()):
        return None
    lengths = {len(v) for v in lists.values()}
    if len(lengths) != 1:
        return None
    n = lengths.pop()
    return records([{k: _plain(v[i]) for k, v in lists.items()} for i in range(n)])


def _plain(v: Any) -> Any:
    return v.item() if isinstance(v, np.generic) else v


def keyed(values: Dict[str, Any], errors: Optional[Dict[str, Any]] = None, *,
          key: str = "name") -> np.ndarray:
    """A dict of scalars (or of dicts of scalars) as a table, one record per key: ``key``, then
    ``value`` and ``err`` (from ``errors``) or the inner dict's fields."""
    rows = []
    for k, v in values.items():
        row: Dict[str, Any] = {key: k}
        if isinstance(v, dict):
            row.update(v)
        else:
            row["value"] = v
            if errors is not None:
                row["err"] = errors.get(k)
        rows.append(row)
    return records(rows)


def of_data(data: Dict[str, Any]) -> Dict[str, np.ndarray]:
    """The tables every result has by its shape: each top-level list of records (dicts), by its
    key (``meta`` and ``config`` are not tables)."""
    out = {}
    for k, v in data.items():
        if k in ("meta", "config") or not isinstance(v, list) or not v:
            continue
        if all(isinstance(r, dict) for r in v):
            out[k] = records(v)
    return out

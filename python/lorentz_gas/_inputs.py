"""The inputs of the analyses as the command line reads them: exact numbers (gaps, radii,
fields) as their exact text, counts as whole numbers, fit windows, thread counts and paths."""

from __future__ import annotations

import decimal
import fractions
import json
import numbers
import os
from typing import Any, Callable, Dict, Optional, Tuple, Union

import numpy as np

from . import _native
from ._keywords import public

Exact = Union[str, float, int, fractions.Fraction, decimal.Decimal]
Count = Union[int, float, str]
Progress = Union[None, bool, Callable[[int], Any]]
PathLike = Union[str, "os.PathLike[str]"]


@public
def agreement_bound(dof: float) -> float:
    """The crate's agreement bound for a value with an error from ``dof + 1`` batches: the
    Student-t quantile with ``dof`` degrees of freedom whose two-sided tail equals that of 4
    normal sigma (6.3e-5); ``agreement_bound(float("inf"))`` is 4 to 11 digits."""
    return _native.agreement_bound(float(dof))


def _exact(name: str, v: Any) -> str:
    """An exact input as the text the command line parses."""
    if isinstance(v, bool):
        raise TypeError(f"{name} must be a number or a string, not bool")
    if isinstance(v, str):
        return v
    if isinstance(v, fractions.Fraction):
        return f"{v.numerator}/{v.denominator}"
    if isinstance(v, decimal.Decimal):
        return str(v)
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        _refuse_lossy(name, v)
        return repr(float(v))
    raise TypeError(f"{name} must be a str, float, int, Fraction or Decimal, not {type(v).__name__}")


def _refuse_lossy(name: str, v: Any) -> None:
    """Refuses a float narrower than a double (numpy.float32 0.1 is 0.100000001490116...: the
    decimal meant is already lost) or one a double cannot hold (numpy.longdouble)."""
    if isinstance(v, float):
        return
    size = getattr(getattr(v, "dtype", None), "itemsize", 8)
    if size < 8:
        raise ValueError(
            f"{name} = {type(v).__name__}({v!r}) holds {float(v)!r}, not the decimal it was "
            f"written as: a {8 * size}-bit float has lost it; pass a str such as '0.1', a Python "
            "float, a Fraction or a Decimal"
        )
    if float(v) != v:
        raise ValueError(
            f"{name} = {type(v).__name__}({v!r}) is not a double: it would be rounded; pass a str, "
            "a Fraction or a Decimal to give it exactly"
        )


Table = Union[str, "os.PathLike[str]", dict]


def _table(scene: str, table: Optional[Table], **given: Any) -> Optional[str]:
    """A table given as data (a dict, or the path of a TOML table file) as the compiled functions
    take it: the table's JSON, every number as its exact text; ``None`` without one."""
    if table is None:
        return None
    extra = [k for k, v in given.items() if v is not None]
    if scene != "triangular" or extra:
        raise ValueError(
            f"table= gives the whole table: leave out {', '.join(['scene='] * (scene != 'triangular') + [k + '=' for k in extra])}"
        )
    return _table_json(table)


def _table_json(table: Table) -> str:
    """The table (a dict, or the path of a TOML table file) as its JSON."""
    if isinstance(table, dict):
        return json.dumps(_table_numbers(table))
    if isinstance(table, (str, os.PathLike)):
        return _native.read_table(os.fspath(table))
    raise TypeError(f"table must be a dict or the path of a TOML table file, not {type(table).__name__}")


def _where(scene: str, table: Optional[Table], w: Any, radius: Any) -> dict:
    """The scene's keys of a compiled function: ``scene``, ``table`` (its JSON, or ``None``),
    ``w`` and ``radius``."""
    return {
        "scene": str(scene),
        "table": _table(scene, table, w=w, radius=radius),
        "w": _optional_exact("w", w),
        "radius": _optional_exact("radius", radius),
    }


def _table_numbers(table: dict) -> dict:
    """The dict with every number of its lattice and disks as exact text (what a table file
    holds); anything else is left for the library to refuse."""
    out = dict(table)
    lattice = out.get("lattice")
    if isinstance(lattice, dict):
        out["lattice"] = {k: _pair(f"lattice.{k}", v) for k, v in lattice.items()}
    disks = out.get("disks")
    if isinstance(disks, (list, tuple)):
        out["disks"] = [_disk(i, d) for i, d in enumerate(disks)]
    return out


def _pair(name: str, v: Any) -> Any:
    if isinstance(v, (list, tuple)) and len(v) == 2:
        return [_exact(name, v[0]), _exact(name, v[1])]
    return v


def _disk(i: int, d: Any) -> Any:
    if not isinstance(d, dict):
        return d
    out = dict(d)
    if "centre" in out:
        out["centre"] = _pair(f"disks[{i}].centre", out["centre"])
    if "radius" in out and not isinstance(out["radius"], (list, dict)):
        out["radius"] = _exact(f"disks[{i}].radius", out["radius"])
    return out


def _optional_exact(name: str, v: Any) -> Optional[str]:
    return None if v is None else _exact(name, v)


def _driving(field: Any, electric: Any, electric_angle: Any) -> Dict[str, Optional[str]]:
    """The fields that drive the gas, each exact or ``None`` (not given): the magnetic field B
    (``field``), the thermostatted electric field E (``electric``) and E's angle in degrees
    (``electric_angle``), as the native calls take them."""
    return {
        "field": _optional_exact("field", field),
        "electric": _optional_exact("electric", electric),
        "electric_angle": _optional_exact("electric_angle", electric_angle),
    }


def _window(name: str, v: Any) -> Tuple[float, float]:
    """A window (from, to) of two numbers."""
    try:
        lo, hi = v
        return (float(lo), float(hi))
    except (TypeError, ValueError) as e:
        raise ValueError(
            f"{name}: {v!r} is not a window (from, to): use two numbers such as (64, 256)"
        ) from e


def _count(name: str, v: Any) -> str:
    """A count as the text the command line parses (whole floats such as 2e9 are accepted)."""
    if isinstance(v, bool):
        raise TypeError(f"{name} must be a whole number, not bool")
    if isinstance(v, str):
        return v
    if isinstance(v, numbers.Integral):
        return str(int(v))
    if isinstance(v, numbers.Real):
        f = float(v)
        return repr(int(f)) if f.is_integer() and abs(f) < 2.0**64 else repr(f)
    raise TypeError(f"{name} must be an int, a whole float or a string, not {type(v).__name__}")


def _counts(**values: Any) -> Dict[str, str]:
    """Counts by name, each as the text the command line parses (:func:`_count`)."""
    return {name: _count(name, v) for name, v in values.items()}


def _threads(v: Optional[Count]) -> Optional[str]:
    return None if v is None else _count("threads", v)


def _path(v: Optional[PathLike]) -> Optional[str]:
    return None if v is None else os.fspath(v)


def _total(v: Any) -> float:
    try:
        return float(str(v).replace("_", ""))
    except ValueError:
        return 0.0


def _many(v: Any) -> bool:
    """Whether ``v`` is several values (a list, tuple or array), not one (text, a number)."""
    return isinstance(v, (list, tuple, np.ndarray))


def _numbers(name: str, v: Any) -> str:
    """Several numbers (a list, tuple or array; or their text ``"0,0.5,1"``) as the text the
    command line parses, each float to the digits that give back its bits."""
    if isinstance(v, str):
        return v
    try:
        values = np.asarray(v, dtype=np.float64).ravel()
    except (TypeError, ValueError) as e:
        raise ValueError(f"{name}: {v!r} is not a list of numbers") from e
    return ",".join(repr(float(x)) for x in values)

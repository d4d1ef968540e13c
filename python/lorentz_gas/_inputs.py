"""The inputs of the analyses as the command line reads them: exact numbers (gaps, radii,
fields) as their exact text, counts as whole numbers, fit windows, thread counts and paths."""

from __future__ import annotations

import decimal
import fractions
import numbers
import os
from typing import Any, Callable, Optional, Tuple, Union

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


def _optional_exact(name: str, v: Any) -> Optional[str]:
    return None if v is None else _exact(name, v)


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

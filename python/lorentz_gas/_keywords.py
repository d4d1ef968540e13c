"""The package's own functions: documented as ``lorentz_gas.<name>`` wherever they are defined,
and naming the keyword meant when a caller misspells one."""

from __future__ import annotations

import difflib
import functools
import inspect
from typing import Any, Callable, TypeVar, cast

F = TypeVar("F", bound=Callable[..., Any])
T = TypeVar("T", bound=type)

#: The package the public names are documented under (``lorentz_gas``).
PACKAGE = __name__.rpartition(".")[0]


def _naming_the_close_match(f: Callable[..., Any]) -> Callable[..., Any]:
    """``f`` refusing an unknown keyword with the ``TypeError`` Python raises, naming the
    keyword ``f`` takes that is closest to it (``colisions=`` → ``collisions``)."""
    sig = inspect.signature(f)
    names = list(sig.parameters)

    @functools.wraps(f)
    def checked(*args: Any, **kwargs: Any) -> Any:
        for k in kwargs:
            if k not in sig.parameters:
                close = difflib.get_close_matches(k, names, n=1)
                hint = (
                    f": did you mean {close[0]!r}?"
                    if close
                    else f"; it takes {', '.join(names)}"
                )
                raise TypeError(f"{f.__name__}() got an unexpected keyword argument {k!r}{hint}")
        return f(*args, **kwargs)

    return checked


def in_package(cls: T) -> T:
    """The class ``cls`` (and the functions defined in it) as the package's own: its repr,
    ``help`` and the doctests of ``lorentz_gas`` name it ``lorentz_gas.<name>``."""
    cls.__module__ = PACKAGE
    for member in vars(cls).values():
        f = member.fget if isinstance(member, property) else member
        if inspect.isfunction(f):
            f.__module__ = PACKAGE
    return cls


def public(f: F) -> F:
    """The function ``f`` as one of the package's: documented (by ``help``, Sphinx and the
    doctests of ``lorentz_gas``) as ``lorentz_gas.<name>``, and refusing a misspelt keyword by
    naming the one meant (:func:`_naming_the_close_match`)."""
    f.__module__ = PACKAGE
    return cast(F, _naming_the_close_match(f))

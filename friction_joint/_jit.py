# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Optional numba acceleration: kernels compiled when numba is installed, plain Python otherwise.

The numerical kernels are written in the subset of Python that numba
compiles.  When numba is installed they are compiled (and cached on disk);
without it the same functions run as plain Python, slower but identical.

The on-disk cache is an optimisation only: a cache that cannot be read or
written (a full disk, a quota, a read-only or foreign cache directory) costs a
compilation, never the command (numba would raise the ``OSError`` from inside
the computation, naming no file the user asked for).
"""
import functools
import os
from types import ModuleType
from typing import Any, Callable, overload, TypeVar

__all__ = ['njit', 'HAVE_NUMBA']

_F = TypeVar('_F', bound=Callable[..., Any])

_numba: ModuleType | None
try:  # optional dependency, imported behind a guard
    if os.environ.get('FRICTION_JOINT_NO_JIT'):
        raise ImportError('disabled by FRICTION_JOINT_NO_JIT')
    import numba as _numba
    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only without numba
    _numba = None
    HAVE_NUMBA = False


def _quiet(method: Callable[..., Any], default: object = None) -> Callable[..., Any]:
    """Return ``method`` with an ``OSError`` turned into returning ``default``."""
    @functools.wraps(method)
    def call(*args: Any, **kwargs: Any) -> Any:
        try:
            return method(*args, **kwargs)
        except OSError:
            return default
    return call


def _optional_cache(dispatcher: _F) -> _F:
    """Make the disk cache of a numba ``dispatcher`` optional: I/O errors skip it."""
    cache = getattr(dispatcher, '_cache', None)
    for name in ('load_overload', 'save_overload', 'flush'):
        method = getattr(cache, name, None)
        if method is not None:
            setattr(cache, name, _quiet(method))
    return dispatcher


def _compile(func: _F, kwargs: dict[str, Any]) -> _F:
    """Return numba's dispatcher of ``func``; uncached if no cache directory is usable."""
    assert _numba is not None                  # called only with numba
    try:
        compiled: _F = _numba.njit(**kwargs)(func)     # a dispatcher: called as func is
        return _optional_cache(compiled)
    except RuntimeError:                       # numba: 'cannot cache function ...'
        if not kwargs.get('cache'):
            raise
        uncached: _F = _numba.njit(**dict(kwargs, cache=False))(func)
        return uncached


@overload
def njit(func: _F, /) -> _F: ...


@overload
def njit(*args: Any, **kwargs: Any) -> Callable[[_F], _F]: ...


def njit(*args: Any, **kwargs: Any) -> Any:
    """Act as ``numba.njit`` with ``cache=True`` if numba is available, else as the identity."""
    if HAVE_NUMBA:
        kwargs.setdefault('cache', True)
        if len(args) == 1 and callable(args[0]):
            return _compile(args[0], kwargs)
        if args:                               # a signature: numba's own handling
            assert _numba is not None
            return _optional_cache_decorator(_numba.njit(*args, **kwargs))
        return lambda func: _compile(func, kwargs)
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return args[0]
    return lambda f: f


def _optional_cache_decorator(decorator: Callable[[_F], _F]) -> Callable[[_F], _F]:
    """Return ``decorator`` (numba's, with a signature) making the cache optional."""
    return lambda func: _optional_cache(decorator(func))

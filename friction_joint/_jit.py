"""Optional numba acceleration.

The numerical kernels are written in the subset of Python that numba
compiles.  When numba is installed they are compiled (and cached on disk);
without it the same functions run as plain Python, slower but identical.
"""
import os

__all__ = ['njit', 'HAVE_NUMBA']

try:  # optional dependency, imported behind a guard
    if os.environ.get('FRICTION_JOINT_NO_JIT'):
        raise ImportError('disabled by FRICTION_JOINT_NO_JIT')
    import numba as _numba
    HAVE_NUMBA = True
except ImportError:  # pragma: no cover - exercised only without numba
    _numba = None
    HAVE_NUMBA = False


def njit(*args, **kwargs):
    """``numba.njit(cache=True)`` if numba is available, else the identity."""
    if HAVE_NUMBA:
        kwargs.setdefault('cache', True)
        return _numba.njit(*args, **kwargs)
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return args[0]
    return lambda f: f

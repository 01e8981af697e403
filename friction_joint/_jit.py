# Copyright 2026 friction_joint maintainers
#
# Licensed under the Apache License, Version 2.0 (the "License");
# you may not use this file except in compliance with the License.
# You may obtain a copy of the License at
#
#     http://www.apache.org/licenses/LICENSE-2.0
#
# Unless required by applicable law or agreed to in writing, software
# distributed under the License is distributed on an "AS IS" BASIS,
# WITHOUT WARRANTIES OR CONDITIONS OF ANY KIND, either express or implied.
# See the License for the specific language governing permissions and
# limitations under the License.

"""
Optional numba acceleration.

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
    """Act as ``numba.njit`` with ``cache=True`` if numba is available, else as the identity."""
    if HAVE_NUMBA:
        kwargs.setdefault('cache', True)
        return _numba.njit(*args, **kwargs)
    if len(args) == 1 and callable(args[0]) and not kwargs:
        return args[0]
    return lambda f: f

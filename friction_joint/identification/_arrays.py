# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers
"""
Array types of the identification's annotations (floating, integer and bool arrays).

``FloatArray`` is an array of any floating dtype: numpy's stubs type many results
(``numpy.linalg``, reductions) as ``floating[Any]`` rather than ``float64``.
"""
from typing import Any

import numpy as np
from numpy.typing import NDArray

__all__ = ['FloatArray', 'IntArray', 'BoolArray']

#: an array of floats
FloatArray = NDArray[np.floating[Any]]
#: an array of integers (indices, counts)
IntArray = NDArray[np.integer[Any]]
#: a bool mask
BoolArray = NDArray[np.bool_]

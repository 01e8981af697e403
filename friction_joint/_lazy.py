# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""A package whose public names load on first use (PEP 562): ``--help`` need not load numba."""
from collections.abc import Callable, Mapping
import importlib
import sys
from typing import Any

__all__ = ['lazy_exports']


def lazy_exports(package: str, homes: Mapping[str, str]
                 ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """
    Return ``(__getattr__, __dir__)`` for a package whose public names load on first use.

    Parameters
    ----------
    package : str
        The package's ``__name__``.
    homes : dict
        Public name -> the module (relative to ``package``) that defines it.

    """
    def __getattr__(name: str) -> Any:
        if name not in homes:
            raise AttributeError(f'module {package!r} has no attribute {name!r}')
        value = getattr(importlib.import_module(homes[name], package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        module = sys.modules[package]
        return sorted(set(vars(module)) | set(getattr(module, '__all__', ())))
    return __getattr__, __dir__

# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
The package version, read from ``package.xml`` (the one place it is written).

An installed package reports its distribution metadata (which ``setup.py``
took from ``package.xml``); a source tree reads ``package.xml`` directly.
"""
import os
import re

__all__ = ['__version__']


def _version():
    xml = os.path.join(os.path.dirname(os.path.dirname(os.path.abspath(__file__))),
                       'package.xml')
    try:
        with open(xml, encoding='utf-8') as fh:
            match = re.search(r'<version>\s*([^<\s]+)\s*</version>', fh.read())
        if match:
            return match.group(1)
    except OSError:
        pass
    import importlib.metadata           # here: it costs a program's start-up 20 ms and more
    try:
        return importlib.metadata.version('friction_joint')
    except importlib.metadata.PackageNotFoundError:
        return 'unknown'


__version__ = _version()

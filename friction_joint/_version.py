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
The package version, read from ``package.xml`` (the one place it is written).

An installed package reports its distribution metadata (which ``setup.py``
took from ``package.xml``); a source tree reads ``package.xml`` directly.
"""
import importlib.metadata
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
    try:
        return importlib.metadata.version('friction_joint')
    except importlib.metadata.PackageNotFoundError:
        return 'unknown'


__version__ = _version()

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

"""Body of the ``record`` / ``replay`` console scripts (``ros2 run friction_joint PROG``)."""
import argparse
import sys

from ..exceptions import RecordingError

__all__ = ['console_main', 'progress_printer']


def progress_printer(quiet=False):
    """Return a ``progress(message)`` callable printing to stderr, or None when ``quiet``."""
    if quiet:
        return None

    def progress(message):
        print(message, file=sys.stderr, flush=True)
    return progress


def console_main(module, argv=None):
    """
    Run the subcommand ``module`` as a console script taking ROS arguments.

    ``argv`` is a full command line including the program name, as for
    ``rclpy.init`` (default ``sys.argv``); ROS arguments (``--ros-args ...``)
    are removed before parsing and passed on to rclpy as ``args.ros_args``.
    A :class:`RecordingError` ends with ``PROG: error: ...`` and status 2,
    Ctrl-C with 130.
    """
    from ..ros._rclpy import ExternalShutdownException, remove_ros_args
    argv = list(sys.argv if argv is None else argv)
    parser = argparse.ArgumentParser(prog=module.NAME, description=module.DESCRIPTION)
    module.add_arguments(parser)
    args = parser.parse_args(remove_ros_args(argv)[1:])
    args.ros_args = argv
    try:
        return module.run(args)
    except RecordingError as exc:
        print(f'{module.NAME}: error: {exc}', file=sys.stderr)
        return 2
    except (KeyboardInterrupt, ExternalShutdownException):
        return 130

# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Child process of the node-parameter fuzz test: many start-ups and run-time sets in one process.

Reads a JSON document from stdin::

    {"startup": [[node, [ros args...]], ...],
     "runtime": [[node, name, value], ...]}

and writes one JSON document to stdout::

    {"startup": [{"rc": int, "stderr": str, "params": {name: value} | null}, ...],
     "runtime": [{"successful": bool, "reason": str, "value": ...,
                  "alive": bool}, ...],
     "declared": {node: {name: value}}}

Start-up runs the node's real ``main(args)`` (the package's start-up path:
arguments checked, rcl initialised, the node built and its parameters
validated) with the executor replaced by one that records the node's
parameters and stops it before it spins, so a case costs a start-up, not a
run.  Everything written to file descriptor 2 during a case (Python's and
rcl's) is captured.  Run-time cases set parameters on one live node per kind
through ``set_parameters``, the path a parameter client's request takes.
"""
import contextlib
import importlib
import json
import math
import os
import sys
import tempfile

NODES = ('joint_sim', 'controller', 'estimator')
CLASSES = {'joint_sim': 'JointSimNode', 'controller': 'ControllerNode',
           'estimator': 'EstimatorNode'}


def _plain(value):
    if isinstance(value, float) and not math.isfinite(value):
        return repr(value)                    # JSON has no nan/inf
    if isinstance(value, (list, tuple)) or type(value).__name__ == 'array':
        return [_plain(v) for v in value]
    return value


class _Recorded:
    params = None


class _StopBeforeSpin:
    """Stand-in executor: records the first node's parameters, then stops the node."""

    def __init__(self, *args, **kwargs):
        pass

    def add_node(self, node):
        _Recorded.params = {name: _plain(p.value) for name, p in node._parameters.items()}
        raise SystemExit(0)

    def shutdown(self, *args, **kwargs):
        """Do nothing: the stand-in holds no thread."""


@contextlib.contextmanager
def _captured_fd2():
    """Capture everything written to fd 2 (Python and C) into the yielded list's string."""
    out = []
    sys.stderr.flush()
    saved = os.dup(2)
    with tempfile.TemporaryFile() as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield out
        finally:
            sys.stderr.flush()
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            out.append(tmp.read().decode('utf-8', 'replace'))


def _startup(cases):
    from rclpy import executors
    original = executors.SingleThreadedExecutor
    executors.SingleThreadedExecutor = _StopBeforeSpin
    results = []
    try:
        for node, args in cases:
            module = importlib.import_module(f'friction_joint.ros.nodes.{node}')
            _Recorded.params = None
            with _captured_fd2() as err:
                rc = module.main(['x'] + list(args))
            results.append({'rc': rc, 'stderr': err[0], 'params': _Recorded.params})
    finally:
        executors.SingleThreadedExecutor = original
    return results


def _runtime(cases, gears):
    import rclpy
    from rclpy.exceptions import ParameterNotDeclaredException
    from rclpy.parameter import Parameter

    from friction_joint.ros.startup import check_ros_args

    results = [None] * len(cases)
    for kind in NODES:
        mine = [(i, c) for i, c in enumerate(cases) if c[0] == kind]
        if not mine:
            continue
        module = importlib.import_module(f'friction_joint.ros.nodes.{kind}')
        args = ['x', '--ros-args', '--params-file', gears[kind]]
        check_ros_args(args)                    # as a start-up does (the -p of the last one)
        rclpy.init(args=args)
        node = getattr(module, CLASSES[kind])()
        try:
            for i, (_, name, value) in mine:
                try:
                    res = node.set_parameters([Parameter(name, value=value)])[0]
                    ok, reason = res.successful, res.reason
                except ParameterNotDeclaredException as exc:   # the service's answer
                    ok, reason = False, f'{type(exc).__name__}: {name}'
                except Exception as exc:        # noqa: BLE001 - the oracle reports it
                    ok, reason = None, f'{type(exc).__name__}: {exc}'
                try:
                    got = (_plain(node.get_parameter(name).value) if node.has_parameter(name)
                           else None)
                    alive = True
                except Exception:               # noqa: BLE001 - the oracle reports it
                    got, alive = None, False
                results[i] = {'successful': ok, 'reason': reason, 'value': got,
                              'alive': alive}
        finally:
            node.destroy_node()
            rclpy.shutdown()
    return results


def main():
    """Run the cases read from stdin; print the results as JSON."""
    doc = json.load(sys.stdin)
    out = {'startup': _startup(doc.get('startup', [])),
           'runtime': _runtime(doc.get('runtime', []), doc.get('gears', {}))}
    sys.stdout.write(json.dumps(out))
    sys.stdout.flush()
    return 0


if __name__ == '__main__':
    sys.exit(main())

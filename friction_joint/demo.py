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
``friction_joint demo --out DIR``: the main job, with a Markdown report of the results.

1. brings the ROS 2 nodes up as separate processes (simulated joint on the
   truth gear, eq. 17 controller and eq. 15 estimator on the model gear, a
   recorder), runs the closed loop in lockstep and records it to
   ``DIR/bag`` (rosbag2, MCAP);
2. plots the recording (tracking, torques, estimated vs measured link torque);
3. runs the classic LuGre experiments and the paper's three test-bed
   experiments;

and collects figures and key numbers in ``DIR/report.md``.

DIR is one output (:class:`~friction_joint.output.OutputSet`): checked before
anything runs (an existing non-empty DIR is an error unless ``force``; one
containing the model or truth file always), built in a temporary sibling
directory and swapped in as a whole at the end, so a failure leaves the old
DIR untouched and no file of an earlier run remains.
"""
import json
import os
import time

from .exceptions import FrictionJointError
from .experiments.classic import EXPERIMENTS as CLASSIC_EXPERIMENTS
from .experiments.classic_report import write_experiment
from .experiments.runner import run_experiment
from .identification.pipeline import run_identify
from .output import OutputSet

__all__ = ['run_demo']

CLASSIC = ('presliding', 'lag', 'breakaway', 'stick-slip')
TESTBED = ('chirp', 'compensation', 'estimation')


def _config(name):
    here = os.path.dirname(os.path.abspath(__file__))
    for base in (os.path.join(here, '..', 'config'),
                 os.path.join(here, '..', '..', '..', '..', 'share', 'friction_joint', 'config')):
        path = os.path.normpath(os.path.join(base, name))
        if os.path.exists(path):
            return path
    raise FrictionJointError(f'cannot find config/{name} next to the package')


def _figures(d):
    return sorted(f for f in os.listdir(d) if f.endswith('.png'))


def run_demo(out, model=None, truth=None, duration_scale=1.0, *, force=False):
    """Run all experiments into ``out`` and write ``out/report.md``; returns its path."""
    model = model or _config('csd25.yaml')
    truth = truth or _config('csd25_truth.yaml')
    with OutputSet(force=force, inputs=[('--model', model), ('--truth', truth)]) as outputs:
        outputs.add_directory(out)
        outputs.check()
        stage = outputs.staging_path(out)
        os.mkdir(stage)
        _run_all(stage, model, truth, duration_scale, outputs.final_path)
        outputs.publish()
    return os.path.join(out, 'report.md')


def _run_all(out, model, truth, duration_scale, relocate):
    """Run everything into the (staged) directory ``out``."""
    lines = ['# friction_joint demo report', '',
             f'Model gear: `{model}`  ', f'Truth (simulated hardware): `{truth}`', '']
    lines += _ros_run(out, model, truth, max(0.5, 3.0 * duration_scale))
    lines += ['## Classic LuGre experiments (Canudas de Wit et al. 1995)', '']
    for name in CLASSIC:
        t0 = time.perf_counter()
        d = os.path.join(out, 'classic')
        write_experiment(name, CLASSIC_EXPERIMENTS[name](), d)
        with open(os.path.join(d, f'{name}.json'), encoding='utf-8') as fh:
            numbers = json.load(fh)
        lines += [f'### {name} ({time.perf_counter() - t0:.1f} s)', '',
                  f'![{name}](classic/{name}.png)', '', '```json',
                  json.dumps({k: v for k, v in numbers.items()
                              if not isinstance(v, list) or len(v) < 12},
                             indent=1), '```', '']
    lines += ["## Simulated test bed: the paper's three applications", '']
    for name in TESTBED:
        t0 = time.perf_counter()
        d = os.path.join(out, name)
        run_experiment(name, model, truth, d, duration_scale=duration_scale)
        with open(os.path.join(d, 'summary.json'), encoding='utf-8') as fh:
            summary = json.load(fh)
        lines += [f'### {name} ({time.perf_counter() - t0:.1f} s)', '']
        lines += [f'![{f}]({name}/{f})' for f in _figures(d)]
        lines += ['', '```json', json.dumps(summary, indent=1), '```', '']
    lines += _identification(out, model, truth, duration_scale, relocate=relocate)
    with open(os.path.join(out, 'report.md'), 'w', encoding='utf-8') as fh:
        fh.write('\n'.join(lines))


def _identification(out, model, truth, duration_scale, *, relocate=None):
    """Record the paper's identification excitation on the simulator and identify."""
    d = os.path.join(out, 'identification')
    bag = os.path.join(d, 'excitation')
    t0 = time.perf_counter()
    run_experiment('identification', None, truth, bag, duration_scale=0.25 * duration_scale)
    t1 = time.perf_counter()
    gear = os.path.join(d, 'identified.yaml')
    report = os.path.join(d, 'report')
    run_identify([bag], model, gear, report_dir=report, relocate=relocate)
    t2 = time.perf_counter()
    with open(gear, encoding='utf-8') as fh:
        header = [ln[2:].rstrip() for ln in fh if ln.startswith('# ')]
    lines = ["## Identification from a recording (the paper's three steps)", '',
             f'`friction_joint experiment identification --truth {os.path.basename(truth)}` '
             f'recorded the excitation in {t1 - t0:.1f} s; `friction_joint identify` fitted the '
             f'structure of `{os.path.basename(model)}` in {t2 - t1:.1f} s and wrote '
             '`identification/identified.yaml`:',
             '', '```'] + header[:40] + ['```', '']
    lines += [f'![{f}](identification/report/{f})' for f in _figures(report)]
    return lines + ['']


def _ros_run(out, model, truth, duration):
    """Bring the nodes up, record, and plot the recording; returns report lines."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import numpy as np

    from .bag import check_lockstep, read_recording
    from .ros.bringup import bringup

    bag = os.path.join(out, 'bag')
    t0 = time.perf_counter()
    bringup(model, truth, duration, record=bag, mode='lockstep', friction='lugre',
            amplitude=0.4, xi0=27.0, log_dir=os.path.join(out, 'logs'))
    wall = time.perf_counter() - t0
    rec = read_recording(bag)
    check = check_lockstep(rec)
    if not check.complete:
        raise FrictionJointError(f'{bag}: the lockstep run lost messages: {check.describe()}; '
                                 'see the node logs in ' + os.path.join(out, 'logs'))
    js, cmd, ext, link = rec.joint_states, rec.joint_command, rec.external_torque, rec.link_torque
    fig, ax = plt.subplots(3, 1, figsize=(8, 8), sharex=True)
    ax[0].plot(cmd.t, cmd.q_d, label='$q_d$')
    ax[0].plot(js.t, js.q, '--', label='$q$ (encoder)')
    ax[0].set_ylabel('position (rad)')
    ax[0].legend()
    qd_on_js = np.interp(js.t, cmd.t, cmd.q_d)
    ax[1].plot(js.t, 1e3 * (qd_on_js - js.q))
    ax[1].set_ylabel('tracking error (mrad)')
    ax[2].plot(link.t, link.tau, label='link torque sensor')
    ax[2].plot(ext.t, ext.effort, label=r'$\hat\tau_{ext}$ (estimator node)')
    ax[2].plot(js.t, js.effort, alpha=0.6, label=r'drive torque $\tau$')
    ax[2].set_ylabel('torque (Nm)')
    ax[2].set_xlabel('time (s)')
    ax[2].legend()
    fig.tight_layout()
    fig.savefig(os.path.join(out, 'ros_run.png'), dpi=110)
    plt.close(fig)
    link_on_ext = np.interp(ext.t, link.t, link.tau)
    settled = ext.t > 0.5
    err = ext.effort[settled] - link_on_ext[settled] if settled.any() else np.array([np.nan])
    counts = ', '.join(f'`{t.topic}` {t.count}' for t in check.topics)
    return ['## ROS 2 nodes in separate processes (lockstep), recorded', '',
            f'`friction_joint bringup --mode lockstep --duration {duration:g}` with recording: '
            f'{duration:g} s simulated in {wall:.1f} s wall; bag `bag/` '
            f'({counts} messages). Every one of the {check.steps} steps is on every loop '
            'topic (checked; the run fails otherwise).', '',
            '![ros run](ros_run.png)', '',
            'Estimator vs link torque sensor after 0.5 s: '
            f'RMS {np.sqrt(np.mean(err ** 2)):.3f} Nm, '
            f'max {np.max(np.abs(err)):.3f} Nm.', '']

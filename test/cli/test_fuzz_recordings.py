# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
Fuzz ``identify`` with recordings whose topics disagree: clocks, signs, units, ranges.

A recording of velocity plateaus of a known static curve is written with one
disagreement drawn on top: a topic's stamps shifted (from a fraction of a
sample, which is harmless, to another clock: 1000 s late, an epoch clock,
1.7e9 s), the position frozen, scaled or mirrored against the
velocity, the temperature out of physics.  A case passes when ``identify``

* exits 0 with a gear file whose static curve matches the truth (3 % over the
  plateau speeds) and whose temperature range covers the recording's, or
* exits 2 with one line naming the recording and nothing written,

so a disagreement is either harmless or refused, never silently misread.
"""
import os

from friction_joint.bag import write_recording
from friction_joint.gear import load_gear
from friction_joint.models import StaticFriction
from hypothesis import event, given, strategies as st
import numpy as np
import pytest

from test_fuzz_inputs import fuzz, guarded

BASE = 'config/csd25_base.yaml'
#: generated cases of disagreeing topics
RECORDING_CASES = 60
SPEEDS = (0.02, 0.2, 1.0, 2.5)
XI = (25.0, 35.0)
DT = 1e-3


def _topics():
    """Return the truth's topics: plateaus both ways, a temperature ramp, a lever load."""
    gear = load_gear(BASE)
    prof = []
    for v in SPEEDS:
        for s in (1, -1):
            ramp = np.sin(np.linspace(0.0, np.pi / 2, 100)) ** 2 * v * s
            prof += [ramp, np.full(600, v * s), ramp[::-1], np.zeros(100)]
    qd = np.concatenate(prof)
    t = 5.0 + DT * np.arange(len(qd))
    q = np.cumsum(qd) * DT + 0.3
    xi = XI[0] + (XI[1] - XI[0]) * (t - t[0]) / (t[-1] - t[0])
    tau_ext = gear.mgl * np.sin(q)
    effort = (StaticFriction(gear.friction).torque(qd, xi, np.abs(tau_ext)) + tau_ext
              + gear.inertia * np.gradient(qd, DT))
    return {'/joint_states': {'t': t, 'q': q, 'qd': qd, 'effort': effort},
            '/joint_temperature': {'t': t[::250], 'xi': xi[::250]},
            '/link_torque': {'t': t, 'tau': tau_ext}}


KINDS = ('shift', 'shift', 'shift', 'frozen', 'scaled', 'mirrored', 'cold', 'hot')


@st.composite
def disagreements(draw):
    """Draw (kind, topic, size) of one disagreement."""
    kind = draw(st.sampled_from(KINDS))
    topic = draw(st.sampled_from(['/joint_temperature', '/link_torque', '/joint_states']))
    size = {'shift': draw(st.sampled_from([0.2 * DT, -0.3 * DT, 30.0, 1000.0, -1000.0,
                                           1.7e9])),
            'scaled': draw(st.sampled_from([180 / np.pi, np.pi / 180, 1000.0, 1e-3])),
            'cold': draw(st.sampled_from([-300.0, -274.0, -1e300])),
            'hot': draw(st.sampled_from([1e300, 5000.0]))}.get(kind, 0.0)
    return kind, topic, size


def _damage(topics, kind, topic, size):
    js = topics['/joint_states']
    if kind == 'shift':                   # stamps are >= 0: a late clock moves the others
        for name, v in topics.items():
            if (name == topic) == (size > 0):
                v['t'] = v['t'] + abs(size)
    elif kind == 'frozen':
        js['q'] = np.full_like(js['q'], js['q'][0])
    elif kind == 'scaled':
        js['q'] = js['q'] * size
    elif kind == 'mirrored':
        js['q'] = -js['q']
    elif kind in ('cold', 'hot'):
        xi = topics['/joint_temperature']['xi']
        xi[len(xi) // 2:] = size


def _matches_truth(out):
    """Return why the identified gear file misreads the truth, or None."""
    got, truth = load_gear(out), load_gear(BASE)
    v = np.concatenate([np.array(SPEEDS), -np.array(SPEEDS)])
    for xi in XI:
        a = StaticFriction(got.friction).torque(v, np.full(len(v), xi), np.zeros(len(v)))
        b = StaticFriction(truth.friction).torque(v, np.full(len(v), xi), np.zeros(len(v)))
        err = np.max(np.abs(a - b) / np.abs(b))
        if err > 0.03:
            return f'static curve off by {100 * err:.1f} % at {xi} degC'
    lo, hi = got.friction.temperature_range
    if lo > XI[0] + 2.0 or hi < XI[1] - 2.0:
        return f"temperature range {lo}..{hi} does not cover the recording's {XI}"
    return None


@pytest.fixture(scope='module')
def truth():
    return _topics()


@pytest.fixture(scope='module')
def no_figures():
    """Render no figure (88 % of identify's time; figures are tested elsewhere)."""
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr('friction_joint.output.render_png', lambda draw, size, dpi=100: b'')
        yield


@pytest.mark.slow
@fuzz(RECORDING_CASES)
@given(case=disagreements())
def test_disagreeing_topics(truth, no_figures, case, tmp_path_factory, capsys):
    kind, topic, size = case
    topics = {k: {f: np.array(x) for f, x in v.items()} for k, v in truth.items()}
    _damage(topics, kind, topic, size)
    d = tmp_path_factory.mktemp('dis')
    rec = write_recording(str(d / 'rec'), topics)
    out = str(d / 'out.yaml')
    rc = guarded(['identify', rec, '--model', BASE, '--out', out, '--presliding', 'skip',
                  '--quiet'])
    err = capsys.readouterr().err
    event(f'{kind} {topic if kind == "shift" else ""}: exit {rc}')
    if rc == 0:
        why = _matches_truth(out)
        assert why is None, f'silent misread of {case}: {why}'
    else:
        lines = err.strip().splitlines()
        assert rc == 2, f'exit {rc}: {err}'
        assert len(lines) == 1 and lines[0].startswith('friction_joint identify: error: '), err
        assert 'rec' in lines[0] and BASE not in lines[0], f'the recording is not blamed: {err}'
        assert not os.path.lexists(out), 'partial output'

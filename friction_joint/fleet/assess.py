# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
From per-recording results to the fleet's verdict: reference point, trends, wear.

:func:`assess_fleet` takes the manifest entries and the per-recording
results (:func:`~friction_joint.fleet.recording.analyse_recording`) and

1. fixes the fleet's **reference operating point** from the data: xi_ref is
   the median over the analysed recordings of their mean plateau temperature
   (clipped to the model gear file's ``temperature_range``), v_ref the median
   of their median plateau speed; tau_L = 0;
2. evaluates every recording there
   (:func:`~friction_joint.fleet.recording.reference_friction`): the
   *reference friction* (the friction torque at +-v_ref, xi_ref, no load) and
   F_c at xi_ref, each with its standard error;
3. runs the wear test per joint (:func:`~friction_joint.fleet.trend.trend_test`)
   on the reference friction (each recording's standard error pulled half-way,
   in variance, towards the fleet's median: a fit to a few plateaus estimates
   its own scatter poorly), and, for comparison, the same test on the raw
   mean friction of the plateaus (no temperature or load compensation: what
   a naive monitor sees).  The extra variance is estimated over the fleet, per
   quantity.

Travel: the manifest's ``travel`` column when every recording of the joint
has it, else the running sum of the recordings' own travel.
"""
from __future__ import annotations

from collections.abc import Sequence
import dataclasses
import datetime
import statistics
from typing import Any, cast, TYPE_CHECKING

import numpy as np

from .recording import reference_friction
from .trend import BOOTSTRAP, extra_variance, trend_test, WEAR_ALPHA

if TYPE_CHECKING:
    from .manifest import ManifestEntry
    from .recording import RecordingResult
    from ..gear import GearParams

__all__ = ['TREND_QUANTITIES', 'FleetAssessment', 'assess_fleet', 'reference_point']

#: trend quantities: the compensated reference friction and the naive raw mean
TREND_QUANTITIES = ('reference', 'raw')
_DAY = 86400.0


@dataclasses.dataclass
class FleetAssessment:
    """
    The fleet's verdict.

    Attributes
    ----------
    xi_ref, v_ref : float
        The reference point (degC, rad/s; tau_L = 0); v_ref None when no recording
        could be analysed.
    joints : dict
        Joint id -> ``wear``, ``onset`` (ISO time or None), ``rate`` (dict), ``evidence``
        (dict), ``series`` (per recording of the joint: time, days, travel, values).
    recordings : list of dict
        One row per manifest entry (status, reason, reference friction, ranges).
    extra_sd : dict
        Quantity -> the fleet's extra standard deviation.

    """

    xi_ref: float
    v_ref: float | None
    joints: dict
    recordings: list
    extra_sd: dict

    def to_dict(self) -> dict[str, Any]:
        """Return plain JSON types (``fleet.json``)."""
        return {'reference_point': {'xi_ref': self.xi_ref, 'v_ref': self.v_ref, 'tau_l': 0.0},
                'extra_sd': dict(self.extra_sd),
                'joints': {j: {k: v for k, v in d.items() if k != 'series'}
                           for j, d in self.joints.items()},
                'recordings': list(self.recordings)}


def reference_point(results: Sequence[RecordingResult | None],
                    gear: GearParams) -> tuple[float, float | None]:
    """
    Return ``(xi_ref, v_ref)`` of the analysed recordings (module docstring).

    Parameters
    ----------
    results : list of RecordingResult or None
        Per recording, :func:`~friction_joint.fleet.recording.analyse_recording`'s result.
    gear : GearParams
        The model gear file (its temperature range bounds xi_ref).

    Returns
    -------
    xi_ref : float
        Reference temperature (degC).
    v_ref : float or None
        Reference speed (rad/s); None when no recording could be analysed.

    """
    ok = [r for r in results if r and r.ok]
    lo, hi = gear.friction.temperature_range
    if not ok:
        return 0.5 * (lo + hi), None
    # an ok result has plateaus, hence its mean temperature and speed
    xi = statistics.median(cast(float, r.xi_mean) for r in ok)
    return float(min(max(xi, lo), hi)), float(statistics.median(cast(float, r.speed) for r in ok))


def _row(entry, res, ref):
    row = {'joint': entry.joint, 'time': entry.time.isoformat(), 'recording': entry.recording,
           'status': res.status, 'reason': res.reason, 'cached': res.cached}
    for key in ('raw_friction', 'raw_friction_se', 'travel', 'plateaus', 'xi_mean', 'speed'):
        row[key] = getattr(res, key)
    row['xi_range'] = None if res.xi_range is None else list(res.xi_range)
    row['load_range'] = None if res.load_range is None else list(res.load_range)
    row['terms'] = ['%s[%d]' % (n, i) for n, i in res.terms]
    if ref:
        row.update({'reference_friction': ref['torque'], 'reference_friction_se': ref['torque_se'],
                    'fc_ref': ref['fc'], 'fc_ref_se': ref['fc_se']})
    else:
        row.update(dict.fromkeys(('reference_friction', 'reference_friction_se', 'fc_ref',
                                  'fc_ref_se')))
    row['odometer'] = entry.travel
    row['metadata'] = dict(entry.metadata)
    return row


def _series(entries, rows):
    """Per joint: the analysed recordings in time order with days and travel."""
    by_joint = {}
    for e, r in zip(entries, rows, strict=True):
        by_joint.setdefault(e.joint, []).append((e, r))
    out = {}
    for joint, items in by_joint.items():
        items.sort(key=lambda it: it[0].time)
        t0 = items[0][0].time
        odometer = all(e.travel is not None for e, _ in items)
        acc, pts = 0.0, []
        for e, r in items:
            if r['status'] == 'ok':
                acc += r['travel'] or 0.0
            if r['status'] != 'ok':
                continue
            pts.append({'time': e.time.isoformat(), 'days': (e.time - t0).total_seconds() / _DAY,
                        'travel': e.travel if odometer else acc,
                        'reference': r['reference_friction'], 'reference_se':
                        r['reference_friction_se'], 'raw': r['raw_friction'],
                        'raw_se': r['raw_friction_se'], 'xi': r['xi_mean'],
                        'xi_range': r['xi_range'], 'fc': r['fc_ref'], 'fc_se': r['fc_ref_se']})
        out[joint] = {'start': t0, 'points': pts, 'count': len(items),
                      'failed': sum(r['status'] != 'ok' for _, r in items),
                      'travel_source': 'manifest' if odometer else 'recordings'}
    return out


def _shrunk(series, q):
    """Return per joint the standard errors of ``q`` pulled half-way (variance) to the median."""
    var = [p[q + '_se'] ** 2 for s in series.values() for p in s['points']]
    m = float(np.median(var)) if var else 0.0
    return {j: np.sqrt(0.5 * np.array([p[q + '_se'] ** 2 for p in s['points']], float) + 0.5 * m)
            for j, s in series.items()}


def _verdict(s, q, se, extra, alpha, n_boot, seed):
    pts = s['points']
    if len(pts) < 2:
        return None
    col = (lambda k: np.array([p[k] for p in pts], float))
    return trend_test(col('days'), col('travel'), col(q), se, extra_var=extra,
                      alpha=alpha, n_boot=n_boot, seed=seed)


def assess_fleet(entries: Sequence[ManifestEntry], results: Sequence[RecordingResult],
                 gear: GearParams, *, alpha: float = WEAR_ALPHA, n_boot: int = BOOTSTRAP,
                 seed: int = 0) -> FleetAssessment:
    """
    Assess a fleet (module docstring).

    Parameters
    ----------
    entries : list of ManifestEntry
        The manifest.
    results : list of RecordingResult
        Per entry, :func:`~friction_joint.fleet.recording.analyse_recording`'s result.
    gear : GearParams
        The model gear file.
    alpha, n_boot, seed
        Of the wear test.

    Returns
    -------
    FleetAssessment

    """
    xi_ref, v_ref = reference_point(results, gear)
    rows = []
    for e, res in zip(entries, results, strict=True):
        ref = (reference_friction(res, gear, xi_ref, v_ref)
               if res.ok and v_ref is not None else None)       # v_ref: one is ok
        rows.append(_row(e, res, ref))
    series = _series(entries, rows)
    extra, ses = {}, {}
    for q in TREND_QUANTITIES:
        ses[q] = _shrunk(series, q)
        extra[q] = extra_variance(([p['travel'] for p in s['points']], [p[q] for p in s['points']],
                                   ses[q][j]) for j, s in series.items())
    joints = {}
    for k, (joint, s) in enumerate(sorted(series.items())):
        tests = {q: _verdict(s, q, ses[q][joint], extra[q], alpha, n_boot, seed + k)
                 for q in TREND_QUANTITIES}
        main = tests['reference']
        entry = {'wear': bool(main and main.wear), 'onset': None, 'rate': None,
                 'recordings': s['count'], 'failed': s['failed'], 'series': s,
                 'evidence': {'test': 'hinge vs no wear, parametric bootstrap',
                              'alpha': alpha, 'travel_source': s['travel_source']}}
        if main is None:
            entry['evidence']['note'] = (f'{len(s["points"])} analysed recordings: too few '
                                         'for the wear test')
        else:
            level = max(abs(main.level), 1e-12)
            entry['rate'] = {'per_day': main.rate_per_day, 'per_day_se': main.rate_per_day_se,
                             'per_travel': main.rate_per_travel,
                             'per_travel_se': main.rate_per_travel_se,
                             'relative_per_day': main.rate_per_day / level,
                             'unit': 'N m per day, N m per rad of travel'}
            if main.wear:
                entry['onset'] = (s['start'] + datetime.timedelta(days=main.onset_day)).isoformat(
                    timespec='seconds')
            entry['evidence'].update(main.to_dict())
            entry['evidence']['onset_time_range'] = [
                (s['start'] + datetime.timedelta(days=d)).isoformat(timespec='seconds')
                for d in main.onset_range]
        raw = tests['raw']
        entry['evidence']['raw_mean_friction'] = (
            None if raw is None else {'wear': raw.wear, 'p_value': raw.p_value,
                                      'onset_day': raw.onset_day, 'axis': raw.axis})
        joints[joint] = entry
    return FleetAssessment(xi_ref, v_ref, joints, rows,
                           {q: float(np.sqrt(v)) for q, v in extra.items()})

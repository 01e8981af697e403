"""The ``diagnose`` command (CONTRACT section 5).

    friction_joint diagnose RECORDING [RECORDING ...] --model BASE.yaml --out DIR
                            [--effects thermal,load,...] [--joint NAME] [--quiet]

Fits BASE's structure to the recordings, names the missing effects and
writes ``DIR/report.json``, ``DIR/extended.yaml``, ``DIR/report.md`` and
figures (method: :mod:`friction_joint.diagnosis.pipeline`).  Everything is computed and
rendered first, then written atomically (report.json last); on an error
nothing is written and the command exits with status 2.
"""
import os
import sys
import time

import yaml

from ..diagnosis.pipeline import EFFECTS, diagnose
from ..exceptions import FrictionJointError, GearConfigError
from ..gear import gear_from_dict, load_gear
from ..output import json_bytes, write_files

__all__ = ['run_diagnose', 'register']


def _gear_yaml(gear, header):
    text = yaml.safe_dump(gear.to_dict(), sort_keys=False, default_flow_style=None)
    doc = yaml.safe_load(text)                    # must load like a gear file does
    gear_from_dict(doc['/**']['ros__parameters'], source='extended.yaml')
    return ''.join(f'# {ln}\n' for ln in header.splitlines()) + text


def run_diagnose(paths, model_path, out, effects=EFFECTS, joint_name=None, progress=None):
    """Diagnose and write the result directory; returns the paths written."""
    start = time.perf_counter()
    base = load_gear(model_path)
    diag = diagnose(paths, base, effects=effects, joint_name=joint_name, progress=progress)
    t0 = time.perf_counter()
    from ..diagnosis.report import figures, markdown
    figs = figures(diag)
    diag.report['timing']['report_s'] = time.perf_counter() - t0
    rep = diag.report
    header = (f'Extended by "friction_joint diagnose" from {os.path.abspath(model_path)}\n'
              f'named causes: {", ".join(rep["named_causes"]) or "none"}\n'
              f'held-out torque RMSE {rep["baseline"]["torque_rmse"]:.4f} -> '
              f'{rep["extended"]["torque_rmse"]:.4f} Nm\n'
              'recordings: ' + ', '.join(os.path.abspath(p) for p in paths))
    gear_text = _gear_yaml(diag.gear, header)
    rep['model_file'] = os.path.abspath(model_path)
    rep['extended_file'] = os.path.abspath(os.path.join(out, 'extended.yaml'))
    rep['timing']['total_s'] = time.perf_counter() - start
    md = markdown(diag, [n for n, _ in figs], model_path)
    targets = figs + [('report.md', md.encode('utf-8')),
                      ('extended.yaml', gear_text.encode('utf-8')),
                      ('report.json', json_bytes(rep))]
    paths_written = write_files(out, targets)
    if progress:
        progress('timing: ' + ', '.join(f'{k} {v:.2f} s' for k, v in rep['timing'].items()))
    return paths_written


def _parse_effects(text):
    if text is None:
        return EFFECTS
    effs = tuple(e.strip() for e in text.split(',') if e.strip())
    bad = [e for e in effs if e not in EFFECTS]
    if bad or not effs:
        raise GearConfigError(f'--effects: unknown effect(s) {", ".join(bad) or "(none given)"}; '
                              f'known: {", ".join(EFFECTS)}')
    return effs


def _run(args):
    def progress(msg):
        print(msg, file=sys.stderr, flush=True)
    if os.path.exists(args.out) and not os.path.isdir(args.out):
        raise FrictionJointError(f'--out {args.out} exists and is not a directory')
    written = run_diagnose(args.recordings, args.model, args.out,
                           effects=_parse_effects(args.effects), joint_name=args.joint,
                           progress=None if args.quiet else progress)
    with open(written[-1], encoding='utf-8') as fh:
        import json
        named = json.load(fh)['named_causes']
    print(f'named causes: {", ".join(named) or "none"}; wrote {args.out}/report.json, '
          f'{args.out}/extended.yaml, {args.out}/report.md')
    return 0


def register(subparsers):
    """Add the ``diagnose`` subcommand."""
    parser = subparsers.add_parser(
        'diagnose', help='name the effects a friction model misses, extend it (CONTRACT 5)',
        description='Fit BASE.yaml\'s structure to recordings, test every candidate effect ('
                    + ', '.join(EFFECTS) + ') on held-out data, name the significant ones and '
                    'write DIR/report.json, DIR/extended.yaml and DIR/report.md with figures.')
    parser.add_argument('recordings', nargs='+', metavar='RECORDING',
                        help='rosbag2 directories or .mcap files')
    parser.add_argument('--model', required=True, metavar='BASE.yaml', help='base gear file')
    parser.add_argument('--out', required=True, metavar='DIR', help='result directory')
    parser.add_argument('--effects', default=None, metavar='E1,E2,...',
                        help='candidate effects to test (default: all)')
    parser.add_argument('--joint', default=None, metavar='NAME',
                        help='joint to read (default: the gear\'s joint_name, else the first)')
    parser.add_argument('--quiet', action='store_true', help='no progress messages')
    parser.set_defaults(func=_run)
    return parser

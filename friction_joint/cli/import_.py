# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint import``: foreign logs (CSV/TSV/NPZ) -> the topics of a recording.

``friction_joint import LOG [LOG ...] --out REC --time COL[:unit] --position ... ``.

Outputs: docs/interfaces.md (recordings).

Turns CSV/TSV/NPZ logs (one run per file) into a recording (method and
conventions: :mod:`friction_joint.bag.importer`).  The columns and units come
from the options or from ``--mapping FILE`` (YAML with the same keys; options
given on the command line win).  The recording is built next to REC and
renamed into place; an existing REC is an error unless ``--force``; on an
error nothing is written and the command exits with status 2.  How the columns
were converted is printed and written into REC's ``metadata.yaml``
(``custom_data``, key ``friction_joint.import``).
"""
import argparse
import sys

from ..exceptions import RecordingError

__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'import'
HELP = 'turn CSV/TSV/NPZ logs into a recording'
DESCRIPTION = ('Turn CSV/TSV/NPZ logs (one run per file, kept as separate pieces) into a '
               'recording: columns and units from the options or --mapping, linear devices '
               'mapped to the joint with --radius, irregular stamps resampled, a log of the '
               'friction itself written as the effort (--friction), a motor current '
               'converted to the joint torque (--current with --torque-constant K and '
               '--gear-ratio N: torque = current x K x N).')

_TORQUES = 'Nm, Nmm, mNm, kNm; N, kN, mN, uN'
_COLUMNS = (('time', 's, ms, us, ns, min, h'), ('position', 'rad, deg, rev; m, cm, mm, um'),
            ('velocity', 'rad/s, deg/s, rev/s, rpm; m/s, mm/s, um/s (default: centred '
                         'difference)'),
            ('torque', f'drive torque: {_TORQUES}'),
            ('current', 'motor current, instead of --torque: A, mA (torque = current x '
                        '--torque-constant x --gear-ratio)'),
            ('friction', f'friction logged directly, instead of --torque: {_TORQUES}'),
            ('load', f'measured external torque tau_ext: {_TORQUES}'),
            ('temperature', 'gear temperature: degC, K, degF'))


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``import`` arguments to ``parser``."""
    parser.add_argument('logs', nargs='+', metavar='LOG',
                        help='text logs (comma, tab, semicolon or whitespace delimited, one '
                             'header line) or .npz files; one run each')
    parser.add_argument('--out', required=True, metavar='REC',
                        help='recording to write (rosbag2 directory, or a .mcap file)')
    for name, units in _COLUMNS:
        parser.add_argument(f'--{name}', default=None, metavar='COL[:unit]',
                            help=f'column (header name or 0-based index); units {units}')
    parser.add_argument('--mapping', default=None, metavar='FILE',
                        help='YAML with the column keys above (and radius, unwrap, '
                             'flip_friction, skip_rows, velocity_from_position, '
                             'torque_constant, gear_ratio)')
    parser.add_argument('--radius', type=float, default=None, metavar='R',
                        help='radius (m) of a linear device: q = x / R, tau = F R (default 1)')
    parser.add_argument('--torque-constant', type=float, default=None, metavar='K',
                        help='torque constant (N m/A, motor side) of the --current column')
    parser.add_argument('--gear-ratio', type=float, default=None, metavar='N',
                        help='gear ratio N of the --current column: joint torque = current x '
                             'K x N (default 1)')
    parser.add_argument('--unwrap', action='store_true', default=None,
                        help='unwrap an angle logged modulo one turn')
    parser.add_argument('--flip-friction', action='store_true', default=None,
                        help='negate the --friction column (a log of the force on the moving '
                             'body, which opposes motion)')
    parser.add_argument('--skip-rows', type=int, default=None, metavar='N',
                        help='lines to skip before the header line (default 0)')
    parser.add_argument('--velocity-from-position', action='store_true', default=None,
                        help="write the position's centred difference as the velocity (a "
                             '--velocity column is then not read): for a logged velocity that '
                             'disagrees with the position (other units, the opposite sign)')
    parser.add_argument('--joint', default='joint', metavar='NAME',
                        help='joint name of the recording (default: joint)')
    parser.add_argument('--force', action='store_true', help='replace an existing REC')
    parser.add_argument('--quiet', action='store_true', help='print only warnings')
    return parser


def run(args: argparse.Namespace) -> int:
    """Import the logs and write the recording; prints the conversions used."""
    import os

    from ..bag import check_motor, import_logs, load_mapping, parse_column, write_recording
    from ..output import OutputSet

    columns, options = ({}, {}) if args.mapping is None else load_mapping(args.mapping)
    for name, _ in _COLUMNS:
        spec = getattr(args, name)
        if spec is not None:
            columns[name] = parse_column(name, spec, f'--{name}')
    for key in ('radius', 'unwrap', 'flip_friction', 'skip_rows', 'velocity_from_position',
                'torque_constant', 'gear_ratio'):
        if getattr(args, key) is not None:
            options[key] = getattr(args, key)
    if options.get('skip_rows', 0) < 0:
        raise RecordingError('--skip-rows must be >= 0')
    for key in ('torque_constant', 'gear_ratio'):
        if getattr(args, key) is not None:
            check_motor(key, getattr(args, key))
    out = os.fspath(args.out)
    inputs = [('LOG', p) for p in args.logs] + [('--mapping', args.mapping)]
    with OutputSet(force=args.force, inputs=inputs, error=RecordingError) as outputs:
        if out.endswith('.mcap'):
            outputs.add_file(out)
        else:
            outputs.add_directory(out)
        outputs.check()
        log = import_logs(args.logs, columns, joint_name=args.joint, **options)
        try:
            write_recording(outputs.staging_path(out), log.topics, joint_name=args.joint,
                            custom_data=log.metadata())
        except OSError as exc:                      # a full disk, a failing device
            raise RecordingError(f'cannot write {out}: {exc.strerror or exc}; nothing was '
                                 'written') from None
        outputs.publish()
    for line in log.warnings:
        print(f'friction_joint import: warning: {line}', file=sys.stderr)
    if not args.quiet:
        for line in log.notes:
            print(line)
        js = log.topics['/joint_states']
        where = ('' if out.endswith('.mcap') else
                 ' (conversions in its metadata.yaml, custom_data friction_joint.import)')
        print(f'wrote {out}: {len(js["t"])} samples, {js["t"][-1] - js["t"][0]:.3f} s, topics '
              f'{", ".join(log.topics)}{where}')
    return 0

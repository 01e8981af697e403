# SPDX-License-Identifier: Apache-2.0
# Copyright 2026 friction_joint maintainers

"""
``friction_joint recover PATH OUT``: a recording from a truncated MCAP file.

See :func:`friction_joint.bag.recover.recover_recording`.
"""
import argparse


__all__ = ['NAME', 'HELP', 'DESCRIPTION', 'add_arguments', 'run']

NAME = 'recover'
HELP = "turn a truncated MCAP file (a killed recorder's) into a recording"
DESCRIPTION = ('Read a truncated MCAP file (a recorder killed with SIGKILL, a full disk) up to '
               'where it ends and write the messages it holds as a sealed rosbag2 recording '
               '(metadata.yaml + .mcap); prints the messages recovered per topic.  PATH is the '
               '.mcap file, its directory, or the hidden staging directory a killed '
               '"friction_joint record OUT" left beside OUT (.OUT.rec-XXXXXXXX.tmp), which is '
               'removed once OUT is complete (unless --keep).')


def add_arguments(parser: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """Add the ``recover`` arguments to ``parser``."""
    parser.add_argument('path', metavar='PATH',
                        help="truncated .mcap file, its directory, or a recorder's staging "
                             'directory (.OUT.rec-XXXXXXXX.tmp)')
    parser.add_argument('out', metavar='OUT',
                        help='recording to write (rosbag2 directory; a name ending in .mcap '
                             'gives a bare MCAP file)')
    parser.add_argument('--force', action='store_true', help='replace an existing OUT')
    parser.add_argument('--keep', action='store_true',
                        help='keep a recovered staging directory (default: removed once OUT '
                             'is written)')
    return parser


def run(args: argparse.Namespace) -> int:
    """Recover; prints the counts per topic and what was lost."""
    from ..bag.recover import recover_recording
    from ..bag.staging import FLUSH_PERIOD

    res = recover_recording(args.path, args.out, force=args.force, keep=args.keep)
    total = sum(res.counts.values())
    detail = ', '.join(f'{t}: {n}' for t, n in res.counts.items())
    print(f'recovered {total} messages ({detail}) from {res.source} to {res.out}, '
          f'log times {res.span[0]:.3f}-{res.span[1]:.3f} s')
    if res.complete and not res.unreadable:
        print('the file was complete: nothing was lost')
    elif res.complete:
        print('the file was complete but for the unreadable chunks named above')
    else:
        print(f'the file was cut short ({res.reason}; {res.lost_bytes} bytes after the last '
              f'whole record): what the recorder received after its last flush (it flushes '
              f'every {FLUSH_PERIOD:g} s) is not in it')
    if res.removed:
        print(f'removed the staging directory {res.removed}')
    elif res.staging:
        print(f'kept the staging directory {res.staging}')
    return 0

"""``friction_joint demo --out DIR``: the main job, with a Markdown report of the results.

Runs every experiment the package offers on the shipped CSD-25 files and
collects their figures and key numbers in ``DIR/report.md``.
"""
import json
import os
import time

from .exceptions import FrictionJointError

__all__ = ['run_demo', 'register']

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


def run_demo(out, model=None, truth=None, duration_scale=1.0):
    """Run all experiments into ``out`` and write ``out/report.md``; returns its path."""
    from .cli import main as cli_main
    model = model or _config('csd25.yaml')
    truth = truth or _config('csd25_truth.yaml')
    os.makedirs(out, exist_ok=True)
    lines = ['# friction_joint demo report', '',
             f'Model gear: `{model}`  ', f'Truth (simulated hardware): `{truth}`', '']
    lines += ['## Classic LuGre experiments (Canudas de Wit et al. 1995)', '']
    for name in CLASSIC:
        t0 = time.perf_counter()
        d = os.path.join(out, 'classic')
        if cli_main(['classic', name, '--out', d]) != 0:
            raise FrictionJointError(f'classic {name} failed')
        with open(os.path.join(d, f'{name}.json'), encoding='utf-8') as fh:
            numbers = json.load(fh)
        lines += [f'### {name} ({time.perf_counter() - t0:.1f} s)', '',
                  f'![{name}](classic/{name}.png)', '', '```json',
                  json.dumps({k: v for k, v in numbers.items() if not isinstance(v, list) or len(v) < 12},
                             indent=1), '```', '']
    lines += ['## Simulated test bed: the paper\'s three applications', '']
    for name in TESTBED:
        t0 = time.perf_counter()
        d = os.path.join(out, name)
        args = ['experiment', name, '--model', model, '--truth', truth, '--out', d]
        if duration_scale != 1.0:
            args += ['--duration-scale', str(duration_scale)]
        if cli_main(args) != 0:
            raise FrictionJointError(f'experiment {name} failed')
        with open(os.path.join(d, 'summary.json'), encoding='utf-8') as fh:
            summary = json.load(fh)
        lines += [f'### {name} ({time.perf_counter() - t0:.1f} s)', '']
        lines += [f'![{f}]({name}/{f})' for f in _figures(d)]
        lines += ['', '```json', json.dumps(summary, indent=1), '```', '']
    path = os.path.join(out, 'report.md')
    tmp = path + '.tmp'
    with open(tmp, 'w', encoding='utf-8') as fh:
        fh.write('\n'.join(lines))
    os.replace(tmp, path)
    return path


def _cmd(args):
    path = run_demo(args.out, args.model, args.truth, args.duration_scale)
    print(f'report: {path}')
    return 0


def register(sub):
    p = sub.add_parser('demo', help='run the main job and write a report with figures')
    p.add_argument('--out', required=True, help='output directory')
    p.add_argument('--model', help='model gear file (default config/csd25.yaml)')
    p.add_argument('--truth', help='truth gear file (default config/csd25_truth.yaml)')
    p.add_argument('--duration-scale', type=float, default=1.0, help='shorten experiments (e.g. 0.2)')
    p.set_defaults(func=_cmd)

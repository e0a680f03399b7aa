#!/usr/bin/python3
"""The whole per-scan time of `dorado odometry` (summary.json's time_per_scan_ms: ego-velocity, kinematic model,
integration, ground attitude) on xsim's scenario kinds, beside the paper's own code and an older dorado when given.

    benchmarks/odometry/odometry_time_xsim.py --out DIR [--dorado build/apps/dorado] [--baseline OLD/dorado]
        [--paper PAPER] [--kinds hills,flat_fast,car_road,crowded,rotated_mount] [--seed 100] [--reps 3]
        [--duration S] [--xsim ../shared/xsim] [--dorado-args "..."]

Per kind, the scenario (make_scenario.py, then describe.py) is generated once into DIR/data/KIND_sSEED. Then, `reps`
times, each program in turn on the same bag (so that machine load hits them alike): dorado (and --baseline) run
`odometry DIR/data/.../dorado.yaml`; PAPER is an executable built from the paper's code (andresgalu/doppler_odometry)
taking `BAG RADAR_TOPIC` and printing, per radar message, the milliseconds of the node's own per-scan work
(`initialize()` for the first scan, `odometryDopplerOnly()` for the others), one a line. Per program and kind the
median over the runs of each run's median and p95 is printed; `x` = the paper's median / dorado's median (or the
baseline's / dorado's), i.e. how many times faster dorado is.
"""
import argparse
import json
import os
import shlex
import statistics
import subprocess
import sys

import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
KINDS = ['hills', 'flat_fast', 'car_road', 'crowded', 'rotated_mount']


def prepare(xsim, data, kind, seed, duration):
    """Generates and describes one scenario into data (a .tmp folder renamed when complete)."""
    if os.path.exists(os.path.join(data, 'dorado.yaml')):
        return
    tmp = data + '.tmp'
    cmd = [sys.executable, os.path.join(xsim, 'make_scenario.py'), '--out', tmp, '--scenario', kind,
           '--seed', str(seed)] + (['--duration', str(duration)] if duration else [])
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    subprocess.run([sys.executable, os.path.join(xsim, 'describe.py'), tmp], check=True, stdout=subprocess.DEVNULL)
    os.rename(tmp, data)


def percentile(values, q):
    """summary.json's definition: the value at index q * (n - 1) of the sorted values."""
    v = sorted(values)
    return v[int(q * (len(v) - 1))]


def run_dorado(dorado, data, out, extra):
    """(median, p95) of one `dorado odometry` run's time per scan [ms]."""
    cmd = [dorado, 'odometry', os.path.join(data, 'dorado.yaml'), '--out', out, '--accept-implausible'] + extra
    proc = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit('odometry_time_xsim.py: %s failed:\n%s' % (' '.join(cmd), proc.stderr[-2000:]))
    t = json.load(open(os.path.join(out, 'summary.json')))['time_per_scan_ms']
    return t['median'], t['p95']


def run_paper(paper, data):
    """(median, p95) of one run of the paper's code on the scenario's bag [ms]."""
    calib = yaml.safe_load(open(os.path.join(data, 'calibration.yaml')))
    cmd = [paper, os.path.join(data, 'radar.bag'), calib['topics']['radar']]
    proc = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    if proc.returncode != 0:
        sys.exit('odometry_time_xsim.py: %s failed:\n%s' % (' '.join(cmd), proc.stderr[-2000:]))
    times = [float(line) for line in proc.stdout.split()]
    if not times:
        sys.exit('odometry_time_xsim.py: %s printed no time' % ' '.join(cmd))
    return statistics.median(times), percentile(times, 0.95)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--out', required=True)
    ap.add_argument('--dorado', default=os.path.join(ROOT, 'build', 'apps', 'dorado'))
    ap.add_argument('--baseline', help='another dorado binary, timed the same way')
    ap.add_argument('--paper', help="an executable of the paper's code: PAPER BAG RADAR_TOPIC prints ms per scan")
    ap.add_argument('--xsim', default=os.path.join(os.path.dirname(ROOT), 'shared', 'xsim'))
    ap.add_argument('--kinds', default=','.join(KINDS))
    ap.add_argument('--seed', type=int, default=100)
    ap.add_argument('--reps', type=int, default=3)
    ap.add_argument('--duration', type=float, help='seconds (default: each scenario its own)')
    ap.add_argument('--dorado-args', default='', help='added to dorado\'s odometry command line (one string)')
    a = ap.parse_args()
    if a.seed < 100:
        sys.exit('odometry_time_xsim.py: xsim seeds below 100 are kept for acceptance runs')
    programs = [('dorado', a.dorado)] + ([('baseline', a.baseline)] if a.baseline else []) + \
        ([('paper', a.paper)] if a.paper else [])
    for name, path in programs:
        if not os.access(path, os.X_OK):
            sys.exit('odometry_time_xsim.py: --%s %s is not an executable' % (name, path))
    extra = shlex.split(a.dorado_args)
    suffix = '_d%g' % a.duration if a.duration else ''
    rows = []
    for kind in a.kinds.split(','):
        if kind not in KINDS:
            sys.exit('odometry_time_xsim.py: unknown kind %s (one of %s)' % (kind, ', '.join(KINDS)))
        data = os.path.join(a.out, 'data', '%s_s%d%s' % (kind, a.seed, suffix))
        prepare(a.xsim, data, kind, a.seed, a.duration)
        runs = {name: [] for name, _ in programs}
        for r in range(a.reps):
            for name, path in programs:
                if name == 'paper':
                    runs[name].append(run_paper(path, data))
                else:
                    out = os.path.join(a.out, 'runs', '%s_s%d%s' % (kind, a.seed, suffix), '%s%d' % (name, r))
                    runs[name].append(run_dorado(path, data, out, extra))
        row = {'kind': kind}
        for name, _ in programs:
            row[name] = (statistics.median(m for m, _ in runs[name]), statistics.median(p for _, p in runs[name]))
        rows.append(row)
        print('%s done' % kind, file=sys.stderr, flush=True)

    others = [name for name, _ in programs if name != 'dorado']
    head = '%-14s %9s %7s' % ('kind', 'dorado', 'p95')
    for name in others:
        head += ' %9s %7s %6s' % (name, 'p95', 'x')
    print('time per scan [ms], median of %d runs (seed %d)' % (a.reps, a.seed))
    print(head)
    for row in rows:
        line = '%-14s %9.3f %7.3f' % (row['kind'], *row['dorado'])
        for name in others:
            line += ' %9.3f %7.3f %6.2f' % (*row[name], row[name][0] / row['dorado'][0])
        print(line)


if __name__ == '__main__':
    main()

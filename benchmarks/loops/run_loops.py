#!/usr/bin/python3
"""Loop closure on ../shared/xsim: revisits closed, no false loop, robustness to injected false loops,
bounded memory. Prints the numbers of docs/loop_closure.md.

    benchmarks/loops/run_loops.py --out DIR [--dorado build/apps/dorado] [--xsim ../shared/xsim]
        [--seeds 100,101,102] [--kinds hills,flat_fast,car_road,crowded,rotated_mount] [--jobs 2]
        [--skip-kinds] [--skip-memory]

Scenarios are generated once into DIR/data (make_scenario.py, describe.py), runs go to DIR/runs and are
skipped when their summary.json exists (resumable). Per seed:
  loop kind:   dorado map (loop closure on, the default), --no-loops, and --inject-false-loops 0.2;
               scored by revisit_check.py (median / max revisit error), `dorado eval` (ATE, SE(3) aligned),
               the accepted loops' relative poses against the truth, and the revisits of >= 50 m closed
               (every stretch of the drive within 5 m of a place passed >= 200 m of path earlier, 50 m long or
               more, holds the query anchor of an accepted loop).
  other kinds: dorado map with and without loop closure: false loops accepted, ATE on against off.
  memory:      car_road 600 s and its first 60 s (the same drive, --duration 60) under /usr/bin/time -v: peak
               RSS, time per scan in the first and the last minute (scans.csv), loops on vs --no-loops
               (median ms per scan), detection + verification per submap (summary.json), submap MB per km.
An accepted loop is false when its relative pose is more than 5 m or 30 deg from the truth's.
"""
import argparse
import csv
import json
import math
import os
import re
import subprocess
import sys
from concurrent.futures import ThreadPoolExecutor

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
KINDS = ['hills', 'flat_fast', 'car_road', 'crowded', 'rotated_mount']


def run(cmd, log=None, check=True):
    with open(log, 'w') if log else open(os.devnull, 'w') as out:
        r = subprocess.run(cmd, stdout=out, stderr=subprocess.STDOUT)
    if check and r.returncode != 0:
        sys.exit('failed (%d): %s%s' % (r.returncode, ' '.join(cmd), '; see ' + log if log else ''))
    return r


def scenario(args, kind, seed, duration=None):
    name = '%s_s%d' % (kind, seed) + ('_d%d' % duration if duration else '')
    d = os.path.join(args.out, 'data', name)
    if not os.path.exists(os.path.join(d, 'dorado.yaml')):
        cmd = ['/usr/bin/python3', os.path.join(args.xsim, 'make_scenario.py'), '--out', d, '--scenario', kind,
               '--seed', str(seed)]
        if duration:
            cmd += ['--duration', str(duration)]
        run(cmd)
        run(['/usr/bin/python3', os.path.join(args.xsim, 'describe.py'), d])
    return d


def dorado_map(args, data, name, extra, timed=False):
    out = os.path.join(args.out, 'runs', name)
    if not os.path.exists(os.path.join(out, 'summary.json')):
        cmd = [args.dorado, 'map', os.path.join(data, 'dorado.yaml'), '--out', out] + extra
        if timed:
            cmd = ['/usr/bin/time', '-v', '-o', out + '.time'] + cmd
        os.makedirs(os.path.dirname(out), exist_ok=True)
        run(cmd, out + '.log')
    return out


def ate(args, data, out):
    ev = os.path.join(out, 'eval.json')
    if not os.path.exists(ev):
        run([args.dorado, 'eval', '--gt', os.path.join(data, 'groundtruth.tum'), '--est',
             os.path.join(out, 'trajectory.tum'), '--json', ev])
    return json.load(open(ev))['ate_m']['rmse']


def revisit(args, data, out):
    text = subprocess.run(['/usr/bin/python3', os.path.join(args.xsim, 'revisit_check.py'),
                           os.path.join(data, 'groundtruth.tum'), os.path.join(out, 'trajectory.tum')],
                          capture_output=True, text=True, check=True).stdout
    m = re.search(r'median ([\d.]+) m, max ([\d.]+) m over (\d+)', text)
    return (float(m.group(1)), float(m.group(2)), int(m.group(3))) if m else (float('nan'),) * 2 + (0,)


def truth_at(gt, t):
    i = int(np.clip(np.searchsorted(gt[:, 0], t - 1e-6), 0, len(gt) - 1))
    return gt[i]


def yaw_of(q):  # qx qy qz qw
    x, y, z, w = q
    return math.atan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def rot(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def loops_scored(data, out):
    """The accepted loops, each with its error against the truth's relative pose."""
    gt = np.loadtxt(os.path.join(data, 'groundtruth.tum'))
    rows = list(csv.DictReader(open(os.path.join(out, 'loops.csv'))))
    accepted = []
    for r in rows:
        if r['verdict'] != 'accepted':
            continue
        gq, gc = truth_at(gt, float(r['query_t'])), truth_at(gt, float(r['candidate_t']))
        R_c = rot(gc[4:8])
        t_true = R_c.T @ (gq[1:4] - gc[1:4])
        yaw_true = yaw_of(gq[4:8]) - yaw_of(gc[4:8])
        t_loop = np.array([float(r['loop_x_m']), float(r['loop_y_m']), float(r['loop_z_m'])])
        dyaw = math.degrees(math.atan2(math.sin(math.radians(float(r['loop_yaw_deg'])) - yaw_true),
                                       math.cos(math.radians(float(r['loop_yaw_deg'])) - yaw_true)))
        accepted.append(dict(query_t=float(r['query_t']), error_m=float(np.linalg.norm(t_loop - t_true)),
                             error_deg=abs(dyaw)))
    false = [a for a in accepted if a['error_m'] > 5.0 or a['error_deg'] > 30.0]
    return rows, accepted, false


def revisits_closed(data, accepted):
    """Stretches of >= 50 m within 5 m of a place passed >= 200 m earlier: how many, how many hold a loop."""
    gt = np.loadtxt(os.path.join(data, 'groundtruth.tum'))
    xy = gt[:, 1:3]
    path = np.concatenate([[0], np.cumsum(np.linalg.norm(np.diff(xy, axis=0), axis=1))])
    revisiting = np.zeros(len(gt), bool)
    for k in range(len(gt)):
        earlier = path < path[k] - 200.0
        if earlier.any():
            revisiting[k] = np.min(np.linalg.norm(xy[earlier] - xy[k], axis=1)) < 5.0
    stretches, k = [], 0
    while k < len(gt):
        if revisiting[k]:
            j = k
            while j + 1 < len(gt) and revisiting[j + 1]:
                j += 1
            if path[j] - path[k] >= 50.0:
                stretches.append((gt[k, 0], gt[j, 0]))
            k = j + 1
        else:
            k += 1
    closed = sum(any(a <= l['query_t'] <= b for l in accepted) for a, b in stretches)
    return len(stretches), closed


def loop_kind(args, seed):
    data = scenario(args, 'loop', seed)
    on = dorado_map(args, data, 'loop_s%d/on' % seed, [])
    off = dorado_map(args, data, 'loop_s%d/off' % seed, ['--no-loops'])
    inj = dorado_map(args, data, 'loop_s%d/inject20' % seed, ['--inject-false-loops', '0.2'])
    rows, accepted, false = loops_scored(data, on)
    stretches, closed = revisits_closed(data, accepted)
    s = json.load(open(os.path.join(on, 'summary.json')))['loop_closure']
    return dict(seed=seed, revisit_on=revisit(args, data, on), revisit_off=revisit(args, data, off),
                ate_on=ate(args, data, on), ate_off=ate(args, data, off), ate_inject=ate(args, data, inj),
                candidates=len(rows), accepted=len(accepted), false=len(false),
                worst_loop_m=max([a['error_m'] for a in accepted], default=0.0),
                stretches=stretches, closed=closed, submap_ms=s['time_per_submap_ms'])


def other_kind(args, kind, seed):
    data = scenario(args, kind, seed)
    on = dorado_map(args, data, '%s_s%d/on' % (kind, seed), [])
    off = dorado_map(args, data, '%s_s%d/off' % (kind, seed), ['--no-loops'])
    rows, accepted, false = loops_scored(data, on)
    return dict(kind=kind, seed=seed, candidates=len(rows), accepted=len(accepted), false=len(false),
                ate_on=ate(args, data, on), ate_off=ate(args, data, off))


def peak_mb(time_file):
    text = open(time_file).read()
    return int(re.search(r'Maximum resident set size \(kbytes\): (\d+)', text).group(1)) / 1024.0


def scan_ms(out):
    rows = list(csv.DictReader(open(os.path.join(out, 'scans.csv'))))
    t = np.array([float(r['t']) for r in rows])
    ms = np.array([float(r['time_total_ms']) for r in rows])
    return t, ms


def memory(args, seed):
    long_data = scenario(args, 'car_road', seed, 600)
    short_data = scenario(args, 'car_road', seed, 60)
    on = dorado_map(args, long_data, 'car_road_600_s%d/on' % seed, [], timed=True)
    off = dorado_map(args, long_data, 'car_road_600_s%d/off' % seed, ['--no-loops'], timed=True)
    first = dorado_map(args, short_data, 'car_road_60_s%d/on' % seed, [], timed=True)
    t, ms = scan_ms(on)
    _, ms_off = scan_ms(off)
    s = json.load(open(os.path.join(on, 'summary.json')))
    lc = s['loop_closure']
    return dict(seed=seed, peak_600=peak_mb(on + '.time'), peak_600_off=peak_mb(off + '.time'),
                peak_60=peak_mb(first + '.time'), first_min_ms=float(np.median(ms[t < t[0] + 60])),
                last_min_ms=float(np.median(ms[t > t[-1] - 60])), median_on=float(np.median(ms)),
                median_off=float(np.median(ms_off)), path_km=s['path_length_m'] / 1000.0,
                submap_ms=lc['time_per_submap_ms'], submaps_mb_per_km=lc['submaps_mb_per_km'],
                accepted=lc['loops_accepted'], ate_on=ate(args, long_data, on), ate_off=ate(args, long_data, off))


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument('--out', required=True)
    p.add_argument('--dorado', default=os.path.join(ROOT, 'build', 'apps', 'dorado'))
    p.add_argument('--xsim', default=os.path.join(os.path.dirname(ROOT), 'shared', 'xsim'))
    p.add_argument('--seeds', default='100,101,102')
    p.add_argument('--kinds', default=','.join(KINDS))
    p.add_argument('--jobs', type=int, default=2)
    p.add_argument('--skip-kinds', action='store_true')
    p.add_argument('--skip-memory', action='store_true')
    args = p.parse_args()
    args.out = os.path.abspath(args.out)
    if not os.path.isdir(args.xsim):
        args.xsim = '/work/shared/xsim'
    seeds = [int(s) for s in args.seeds.split(',')]
    if min(seeds) < 100:
        sys.exit('--seeds: seeds below 100 are kept for acceptance runs')
    with ThreadPoolExecutor(args.jobs) as pool:
        loops = list(pool.map(lambda s: loop_kind(args, s), seeds))
        others = [] if args.skip_kinds else list(pool.map(lambda ks: other_kind(args, *ks),
                                                          [(k, s) for k in args.kinds.split(',') for s in seeds]))
    print('## xsim loop (%s)\n' % ', '.join(map(str, seeds)))
    print('| seed | revisit median / max [m] on | off | ATE on / off / 20 % injected [m] | candidates | '
          'accepted | false | worst loop error [m] | revisits >= 50 m closed | detect+verify per submap median / p95 [ms] |')
    print('|---|---|---|---|---|---|---|---|---|---|')
    for r in loops:
        print('| %d | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f / %.2f | %d | %d | %d | %.2f | %d of %d | %.1f / %.1f |' % (
            r['seed'], r['revisit_on'][0], r['revisit_on'][1], r['revisit_off'][0], r['revisit_off'][1],
            r['ate_on'], r['ate_off'], r['ate_inject'], r['candidates'], r['accepted'], r['false'],
            r['worst_loop_m'], r['closed'], r['stretches'], r['submap_ms']['median'] if r['submap_ms'] else 0,
            r['submap_ms']['p95'] if r['submap_ms'] else 0))
    if others:
        print('\n## other kinds: false loops, ATE with and without loop closure\n')
        print('| kind | seed | candidates | accepted | false | ATE on [m] | ATE off [m] |')
        print('|---|---|---|---|---|---|---|')
        for r in others:
            print('| %s | %d | %d | %d | %d | %.3f | %.3f |' % (r['kind'], r['seed'], r['candidates'], r['accepted'],
                                                           r['false'], r['ate_on'], r['ate_off']))
    if not args.skip_memory:
        m = memory(args, seeds[0])
        print('\n## car_road 600 s (seed %d, %.2f km)\n' % (m['seed'], m['path_km']))
        print('| peak RSS 600 s on / off [MB] | first 60 s [MB] | ratio | ms per scan first / last minute | '
              'median ms per scan on / off | detect+verify per submap median / p95 [ms] | submaps MB per km | loops | ATE on / off [m] |')
        print('|---|---|---|---|---|---|---|---|---|')
        sm = m['submap_ms'] or {'median': 0, 'p95': 0}
        print('| %.0f / %.0f | %.0f | %.2f | %.2f / %.2f | %.2f / %.2f | %.1f / %.1f | %.2f | %d | %.2f / %.2f |' % (
            m['peak_600'], m['peak_600_off'], m['peak_60'], m['peak_600'] / m['peak_60'], m['first_min_ms'],
            m['last_min_ms'], m['median_on'], m['median_off'], sm['median'], sm['p95'], m['submaps_mb_per_km'],
            m['accepted'], m['ate_on'], m['ate_off']))


if __name__ == '__main__':
    main()

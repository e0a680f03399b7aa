#!/usr/bin/python3
"""The second world in the bench: dorado on ../shared/xsim scenarios, several seeds per
scenario kind, scored against the exact trajectory, with each kind's WORST seed beside its mean.

    benchmarks/xsim/run_xsim.py --out DIR [--dorado build/apps/dorado] [--xsim ../shared/xsim]
        [--kinds hills,flat_fast,car_road,crowded,rotated_mount] [--seeds 100,101,102] [--jobs 2]
        [--map-args "--config VARIANT.yaml"] [--tag NAME] [--duration S]

Per (kind, seed), once, cached in DIR/data/KIND_sSEED (KIND_sSEED_dS with --duration): make_scenario.py, then
describe.py (DIR/data/.../dorado.yaml) and fast_movers.npy (see below). Seeds below 100 are refused (they are kept
for independent acceptance runs). Then three runs per scenario, --jobs at a time, each skipped when its
summary.json exists (the command is resumable; a failed run leaves run.log and no summary.json):
    DIR/runs/KIND_sSEED/odometry          dorado odometry dorado.yaml --masks
    DIR/runs/KIND_sSEED/map_imu           dorado map dorado.yaml --prior imu       (the heading reference)
    DIR/runs/KIND_sSEED/map_doppler[_TAG] dorado map dorado.yaml --prior doppler MAP_ARGS
--map-args goes to the doppler-prior map only; give each variant its own --tag (results_TAG.csv/.md).

Scores (per run): ATE rmse [m] (SE(3) alignment), per-frame RPE rmse translation [mm] / rotation [deg], all from
`dorado eval --json`; the largest |heading error| over the run after aligning the first pose [deg]; map fallbacks
[% of scans] from summary.json; the dynamic mask against point_labels.npz (classes 10 pedestrian, 11 vehicle are
movers, 20 ghosts): precision = movers among the non-ghost points labelled dynamic, recall = movers labelled
dynamic among the movers that reached the fit (label 0 or 1; 2 = filtered before it), and recall on the "fast"
movers only, whose measured Doppler differs from a static point's at the same position, -(p/|p|) . v_sensor with
v_sensor from truth_twist.csv, by more than 0.3 m/s (modulo the ambiguity interval where the radar aliases);
static->1 / static->3 = the share of the static points (not movers, not ghosts) that reached the fit labelled 1 / 3
(precision depends on how many movers a kind has; these do not).
Map runs get --masks when this dorado's `map --help` lists it (labels 0 static, 1 dynamic, 2 filtered, 3 kept
out by the mover rules: 1 and 3 count as dynamic); a run without masks/ is scored on the odometry's.
Heading criterion (the plaza): doppler map's max heading error <= imu map's + 2 deg.

Writes DIR/results[_TAG].csv (one row per kind, seed, run) and DIR/results[_TAG].md (the printed tables).
"""
import argparse
import csv
import glob
import json
import math
import os
import shlex
import shutil
import subprocess
import sys
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import yaml

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
KINDS = ['hills', 'flat_fast', 'car_road', 'crowded', 'rotated_mount']
MOVERS, GHOST = (10, 11), 20
FAST_MPS, HEADING_MARGIN_DEG = 0.3, 2.0
SCENARIO_FILES = ['radar.bag', 'groundtruth.tum', 'truth_twist.csv', 'calibration.yaml', 'point_labels.npz',
                  'scan_stats.csv', 'dorado.yaml', 'fast_movers.npy']
PRINT = threading.Lock()


def log(msg):
    with PRINT:
        print(msg, flush=True)


# ----------------------------------------------------------------------------- scenarios
def fast_movers(d, radar_topic):
    """Per point in bag order: |measured Doppler - a static point's Doppler at its position| > FAST_MPS."""
    import rosbag
    calib = yaml.safe_load(open(os.path.join(d, 'calibration.yaml')))
    v_max = calib['radar_noise'].get('doppler_unambiguous_max_mps')
    twist = np.loadtxt(os.path.join(d, 'truth_twist.csv'), delimiter=',', skiprows=1)
    offs = {f['name']: f['offset'] for f in calib['pointcloud']['fields']}
    out = []
    with rosbag.Bag(os.path.join(d, 'radar.bag')) as bag:
        for j, (_, msg, _) in enumerate(bag.read_messages(topics=[radar_topic])):
            dt = np.dtype({'names': ['x', 'y', 'z', 'doppler'], 'formats': ['<f4'] * 4,
                           'offsets': [offs[k] for k in ('x', 'y', 'z', 'doppler')], 'itemsize': msg.point_step})
            a = np.frombuffer(msg.data, dt, count=msg.width * msg.height)
            p = np.stack([a['x'], a['y'], a['z']], 1).astype(float)
            static = -(p / np.linalg.norm(p, axis=1, keepdims=True)) @ twist[j, 1:4]
            diff = a['doppler'] - static
            if v_max:
                diff = (diff + v_max) % (2 * v_max) - v_max
            out.append(np.abs(diff) > FAST_MPS)
    return np.concatenate(out)


def prepare(xsim, data, kind, seed, duration):
    """Generate + describe one scenario into data (atomically: a .tmp folder renamed when complete)."""
    if all(os.path.exists(os.path.join(data, f)) for f in SCENARIO_FILES):
        return 'cached'
    tmp = data + '.tmp'
    shutil.rmtree(tmp, ignore_errors=True)
    cmd = [sys.executable, os.path.join(xsim, 'make_scenario.py'), '--out', tmp, '--scenario', kind,
           '--seed', str(seed)] + (['--duration', str(duration)] if duration else [])
    subprocess.run(cmd, check=True, stdout=subprocess.DEVNULL)
    subprocess.run([sys.executable, os.path.join(xsim, 'describe.py'), tmp], check=True, stdout=subprocess.DEVNULL)
    topic = yaml.safe_load(open(os.path.join(tmp, 'calibration.yaml')))['topics']['radar']
    fast = fast_movers(tmp, topic)
    n = len(np.load(os.path.join(tmp, 'point_labels.npz'))['labels'])
    if len(fast) != n:
        raise RuntimeError('%s: %d points in the bag, %d labels' % (tmp, len(fast), n))
    np.save(os.path.join(tmp, 'fast_movers.npy'), fast)
    shutil.rmtree(data, ignore_errors=True)
    os.rename(tmp, data)
    return 'generated'


# ----------------------------------------------------------------------------- runs
def run_dorado(dorado, data, out, run, map_args, map_masks):
    """One dorado run into out; returns (status, seconds). Skipped when out/summary.json exists."""
    if os.path.exists(os.path.join(out, 'summary.json')):
        return 'cached', 0.0
    shutil.rmtree(out, ignore_errors=True)  # a half-written run (killed, failed) starts again
    os.makedirs(out)
    ds = os.path.join(data, 'dorado.yaml')
    if run == 'odometry':
        cmd = [dorado, 'odometry', ds, '--out', out, '--masks', '--accept-implausible']
    else:
        cmd = [dorado, 'map', ds, '--prior', run.split('_')[1], '--out', out, '--accept-implausible'] + (['--masks'] if map_masks else [])
        cmd += map_args if run.startswith('map_doppler') else []
    t0 = time.time()
    with open(os.path.join(out, 'run.log'), 'w') as f:
        f.write(' '.join(map(shlex.quote, cmd)) + '\n')
        f.flush()
        rc = subprocess.call(cmd, stdout=f, stderr=subprocess.STDOUT)
    sec = time.time() - t0
    if rc != 0 and os.path.exists(os.path.join(out, 'summary.json')):  # stopped early: not a result
        os.rename(os.path.join(out, 'summary.json'), os.path.join(out, 'summary.failed.json'))
    return ('ok' if rc == 0 else 'FAILED rc=%d (see %s/run.log)' % (rc, out)), sec


# ----------------------------------------------------------------------------- scores
def read_tum(path):
    a = np.loadtxt(path, ndmin=2)
    return np.round(a[:, 0] * 1e9).astype(np.int64), a[:, 1:4], a[:, 4:8]


def yaw(q):
    x, y, z, w = q.T
    return np.arctan2(2 * (w * z + x * y), 1 - 2 * (y * y + z * z))


def quat_mul(a, b):
    ax, ay, az, aw = np.moveaxis(a, -1, 0)
    bx, by, bz, bw = np.moveaxis(b, -1, 0)
    return np.stack([aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
                     aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz], -1)


def max_heading_error_deg(gt_path, est_path):
    """Largest |yaw(gt) - yaw(est)| after rotating the estimate so that its first pose's attitude is the truth's."""
    tg, _, qg = read_tum(gt_path)
    te, _, qe = read_tum(est_path)
    idx = np.searchsorted(tg, te).clip(0, len(tg) - 1)
    ok = np.abs(tg[idx] - te) < 2_000_000
    qg, qe = qg[idx[ok]], qe[ok]
    inv0 = qe[0] * np.array([-1, -1, -1, 1])
    qa = quat_mul(quat_mul(qg[0], inv0)[None], qe)
    err = (yaw(qa) - yaw(qg) + math.pi) % (2 * math.pi) - math.pi
    return float(np.degrees(np.abs(err).max()))


def mask_scores(data, run_dir, odom_dir):
    """Mask precision/recall of movers (see the docstring), on run_dir/masks or else odom_dir/masks."""
    src = next((d for d in (run_dir, odom_dir) if glob.glob(os.path.join(d, 'masks', '*.txt'))), None)
    if src is None:
        return {}
    npz = np.load(os.path.join(data, 'point_labels.npz'))
    labels, offs, stamps = npz['labels'], npz['offsets'], npz['stamps_ns']
    fast = np.load(os.path.join(data, 'fast_movers.npy'))
    scan_of = {int(s): j for j, s in enumerate(stamps)}
    c = dict(tp=0, pred=0, movers=0, fast=0, fast_tp=0, static=0, static_dyn=0, static_rule=0, scans=0, unmatched=0)
    for f in sorted(glob.glob(os.path.join(src, 'masks', '*.txt'))):
        with open(f) as fh:
            head = fh.readline().replace(',', ' ').split()
            stamp = int(head[head.index('stamp_ns') + 1])
            m = np.array([int(x) for x in fh.read().split()], np.int8)
        j = scan_of.get(stamp)
        if j is None or len(m) != offs[j + 1] - offs[j]:
            c['unmatched'] += 1
            continue
        cls, fa = labels[offs[j]:offs[j + 1]], fast[offs[j]:offs[j + 1]]
        used, dyn, mov = m != 2, (m == 1) | (m == 3), np.isin(cls, MOVERS)
        c['scans'] += 1
        c['pred'] += int(np.sum(dyn & (cls != GHOST)))
        c['tp'] += int(np.sum(dyn & mov))
        c['movers'] += int(np.sum(used & mov))
        c['fast'] += int(np.sum(used & mov & fa))
        c['fast_tp'] += int(np.sum(dyn & mov & fa))
        c['static'] += int(np.sum(used & ~mov & (cls != GHOST)))
        c['static_dyn'] += int(np.sum((m == 1) & ~mov & (cls != GHOST)))
        c['static_rule'] += int(np.sum((m == 3) & ~mov & (cls != GHOST)))
    div = lambda a, b: a / b if b else float('nan')
    return dict(mask_source=os.path.relpath(src, os.path.dirname(os.path.dirname(src))),
                mask_precision=div(c['tp'], c['pred']), mask_recall=div(c['tp'], c['movers']),
                mask_recall_fast=div(c['fast_tp'], c['fast']), static_dyn_pct=100 * div(c['static_dyn'], c['static']),
                static_rule_pct=100 * div(c['static_rule'], c['static']),
                movers=c['movers'], fast_movers=c['fast'],
                mask_scans=c['scans'], mask_scans_unmatched=c['unmatched'])


def score(dorado, data, run_dir, odom_dir):
    gt, est = os.path.join(data, 'groundtruth.tum'), os.path.join(run_dir, 'trajectory.tum')
    ev = os.path.join(run_dir, 'eval.json')
    if not os.path.exists(ev) or os.path.getmtime(ev) < os.path.getmtime(est):
        subprocess.run([dorado, 'eval', '--gt', gt, '--est', est, '--json', ev], check=True,
                       stdout=subprocess.DEVNULL)
    e = json.load(open(ev))
    s = json.load(open(os.path.join(run_dir, 'summary.json')))
    scans = s.get('scans_used') or s.get('scans') or 0
    fb = s['fallbacks'] if 'fallbacks' in s else s.get('scans_with_fallback_twist', 0)
    r = dict(ate_m=e['ate_m']['rmse'], rpe_t_mm=1e3 * e['rpe_translation_m']['rmse'],
             rpe_r_deg=e['rpe_rotation_deg']['rmse'], heading_max_deg=max_heading_error_deg(gt, est),
             fallback_pct=100.0 * fb / scans if scans else float('nan'), scans=scans)
    r.update(mask_scores(data, run_dir, odom_dir))
    return r


# ----------------------------------------------------------------------------- tables
COLUMNS = [  # (header, key, format, worse is higher)
    ('map ATE [m]', 'map_ate', '%.3f', True), ('odom ATE [m]', 'odom_ate', '%.3f', True),
    ('map/odom', 'ratio', '%.2f', True), ('map RPE [mm]', 'rpe_t', '%.1f', True),
    ('map RPE [deg]', 'rpe_r', '%.3f', True), ('fallbacks [%]', 'fallback', '%.1f', True),
    ('hdg dop [deg]', 'hdg_dop', '%.2f', True), ('hdg imu [deg]', 'hdg_imu', '%.2f', True),
    ('hdg dop-imu', 'hdg_excess', '%+.2f', True), ('mask P', 'prec', '%.3f', False),
    ('mask R', 'rec', '%.3f', False), ('mask R fast', 'rec_fast', '%.3f', False),
    ('static→1 [%]', 'static_dyn', '%.1f', True), ('static→3 [%]', 'static_rule', '%.1f', True)]


def seed_row(rows, dop):
    g = lambda run, k: rows.get(run, {}).get(k, float('nan'))
    m = lambda k: g(dop, k)
    return dict(map_ate=m('ate_m'), odom_ate=g('odometry', 'ate_m'), ratio=m('ate_m') / g('odometry', 'ate_m'),
                rpe_t=m('rpe_t_mm'), rpe_r=m('rpe_r_deg'), fallback=m('fallback_pct'), hdg_dop=m('heading_max_deg'),
                hdg_imu=g('map_imu', 'heading_max_deg'), hdg_excess=m('heading_max_deg') - g('map_imu', 'heading_max_deg'),
                prec=m('mask_precision'), rec=m('mask_recall'), rec_fast=m('mask_recall_fast'),
                static_dyn=m('static_dyn_pct'), static_rule=m('static_rule_pct'))


def fmt(f, v):
    return '—' if v is None or (isinstance(v, float) and math.isnan(v)) else f % v


def tables(results, kinds, seeds, dop):
    out, pooled_map, pooled_odom = [], [], []
    for kind in kinds:
        per = {s: seed_row(results.get((kind, s), {}), dop) for s in seeds}
        n_ok = sum(1 for s in seeds if not math.isnan(per[s]['map_ate']))
        src = sorted({os.path.basename(results[(kind, s)][dop]['mask_source']) for s in seeds
                      if 'mask_source' in results.get((kind, s), {}).get(dop, {})}) or ['none']
        out += ['', '### %s (%s, seeds %s; %d/%d map runs scored; masks of %s)' % (
            kind, dop, ','.join(map(str, seeds)), n_ok, len(seeds), '+'.join(src)), '',
                '| seed | ' + ' | '.join(c[0] for c in COLUMNS) + ' | heading ok |',
                '|---' * (len(COLUMNS) + 2) + '|']
        for s in seeds:
            r = per[s]
            ok = '—' if math.isnan(r['hdg_excess']) else ('yes' if r['hdg_excess'] <= HEADING_MARGIN_DEG else '**no**')
            out.append('| %d | ' % s + ' | '.join(fmt(c[2], r[c[1]]) for c in COLUMNS) + ' | %s |' % ok)
            pooled_map.append(r['map_ate'])
            pooled_odom.append(r['odom_ate'])
        mean, worst = [], []
        for _, k, f, higher in COLUMNS:
            vals = [(per[s][k], s) for s in seeds if not math.isnan(per[s][k])]
            if not vals:
                mean.append('—')
                worst.append('—')
                continue
            mean.append(f % np.mean([v for v, _ in vals]))
            v, s = (max if higher else min)(vals)
            worst.append('%s (s%d)' % (f % v, s))
        fails = sum(1 for s in seeds if per[s]['hdg_excess'] > HEADING_MARGIN_DEG)
        out.append('| **mean** | ' + ' | '.join(mean) + ' | %d/%d pass |' % (n_ok - fails, n_ok))
        out.append('| **worst** | ' + ' | '.join(worst) + ' | |')
    pm = [v for v in pooled_map if not math.isnan(v)]
    po = [v for v in pooled_odom if not math.isnan(v)]
    out += ['', '**Pooled xsim** (%d kinds x %d seeds): map (%s) ATE mean %s m (worst %s m), odometry ATE mean %s m '
            '(worst %s m)' % (len(kinds), len(seeds), dop, fmt('%.3f', np.mean(pm) if pm else None),
                              fmt('%.3f', max(pm) if pm else None), fmt('%.3f', np.mean(po) if po else None),
                              fmt('%.3f', max(po) if po else None))]
    return '\n'.join(out) + '\n'


# ----------------------------------------------------------------------------- main
def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--out', required=True)
    ap.add_argument('--dorado', default=os.path.join(ROOT, 'build', 'apps', 'dorado'))
    ap.add_argument('--xsim', default=os.path.join(os.path.dirname(ROOT), 'shared', 'xsim'))
    ap.add_argument('--kinds', default=','.join(KINDS))
    ap.add_argument('--seeds', default='100,101,102')
    ap.add_argument('--jobs', type=int, default=2)
    ap.add_argument('--map-args', default='', help='extra arguments of the doppler-prior map (one string)')
    ap.add_argument('--tag', default='', help='names the doppler-prior map variant (runs and results files)')
    ap.add_argument('--duration', type=float, default=None, help='seconds (default: each scenario its own)')
    argv = sys.argv[1:]
    for i, v in enumerate(argv[:-1]):  # `--map-args "--config VARIANT.yaml"`: a value that starts with '--'
        if v == '--map-args':
            argv[i:i + 2] = ['--map-args=' + argv[i + 1]]
            break
    a = ap.parse_args(argv)
    kinds = [k for k in a.kinds.split(',') if k]
    seeds = [int(s) for s in a.seeds.split(',') if s]
    bad = [k for k in kinds if k not in KINDS]
    if bad:
        ap.error('unknown kind(s) %s; xsim has %s' % (','.join(bad), ','.join(KINDS)))
    if any(s < 100 for s in seeds):
        ap.error('seeds below 100 (%s) are kept for independent acceptance runs and are refused: use 100 or above'
                 % ','.join(str(s) for s in seeds if s < 100))
    dorado = os.path.abspath(a.dorado)
    if not os.access(dorado, os.X_OK):
        ap.error('%s: no dorado binary (build it, or give --dorado)' % dorado)
    dop = 'map_doppler' + ('_' + a.tag if a.tag else '')
    map_args = shlex.split(a.map_args)
    out = os.path.abspath(a.out)
    suffix = '_d%g' % a.duration if a.duration else ''
    names = {(k, s): '%s_s%d%s' % (k, s, suffix) for k in kinds for s in seeds}
    data = {ks: os.path.join(out, 'data', n) for ks, n in names.items()}
    rdir = {ks: os.path.join(out, 'runs', n) for ks, n in names.items()}
    runs = ['odometry', 'map_imu', dop]
    map_masks = '--masks' in subprocess.run([dorado, 'map', '--help'], capture_output=True, text=True).stdout

    t_all = time.time()
    n_gen = [0]

    def gen(ks):
        t0 = time.time()
        st = prepare(a.xsim, data[ks], ks[0], ks[1], a.duration)
        with PRINT:
            n_gen[0] += 1
            print('[%d/%d] %s %s ... %.1f s' % (n_gen[0], len(names), names[ks], st, time.time() - t0), flush=True)

    with ThreadPoolExecutor(max(1, a.jobs)) as pool:
        list(pool.map(gen, names))

    tasks = [(ks, run) for ks in names for run in runs]
    n_done, status = [0], {}

    def work(task):
        ks, run = task
        st, sec = run_dorado(dorado, data[ks], os.path.join(rdir[ks], run), run, map_args, map_masks)
        status[task] = st
        with PRINT:
            n_done[0] += 1
            print('[%d/%d] %s %s ... %s' % (n_done[0], len(tasks), names[ks], run.replace('_', ' ', 1),
                                            st if st == 'cached' else '%.1f s%s' % (sec, '' if st == 'ok' else ' ' + st)),
                  flush=True)

    with ThreadPoolExecutor(max(1, a.jobs)) as pool:
        list(pool.map(work, tasks))

    results, rows = {}, []
    for ks in names:
        for run in runs:
            d = os.path.join(rdir[ks], run)
            row = dict(kind=ks[0], seed=ks[1], run=run, status=status[(ks, run)].split(' ')[0])
            if os.path.exists(os.path.join(d, 'summary.json')):
                try:
                    row.update(score(dorado, data[ks], d, os.path.join(rdir[ks], 'odometry')))
                    results.setdefault(ks, {})[run] = row
                except (subprocess.CalledProcessError, OSError, KeyError, ValueError) as e:
                    row['status'] = 'unscored'
                    log('%s %s: not scored: %s' % (names[ks], run, e))
            rows.append(row)
    base = os.path.join(out, 'results' + ('_' + a.tag if a.tag else ''))
    keys = list(dict.fromkeys(k for r in rows for k in r))
    with open(base + '.csv', 'w', newline='') as f:
        w = csv.DictWriter(f, keys)
        w.writeheader()
        w.writerows({k: ('%.6g' % v if isinstance(v, float) else v) for k, v in r.items()} for r in rows)
    text = ('# xsim benchmark%s\n\n`%s`\n\nmap args: `%s`; dorado: `%s`; %.0f s\n' %
            (' (' + a.tag + ')' if a.tag else '', ' '.join(map(shlex.quote, sys.argv[:1] + argv)), a.map_args or '(none)',
             dorado, time.time() - t_all)) + tables(results, kinds, seeds, dop)
    with open(base + '.md', 'w') as f:
        f.write(text)
    print(text)
    print('wrote %s.csv, %s.md' % (base, base))
    failed = [r for r in rows if r['status'] not in ('ok', 'cached')]
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())

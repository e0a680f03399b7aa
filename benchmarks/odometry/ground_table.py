# /usr/bin/python3 benchmarks/odometry/ground_table.py BENCH_OUT
# The ground factor's decision table (configs/benchmark_ground.yaml): per sequence (seeds NAME, NAME_sK averaged) and run,
# the RMS roll and pitch errors [deg] (Euler ZYX of R_gt_rel^T R_est_rel, first pose aligned, as the ATE rotation),
# the ATE rotation [deg], the ATE [m] and the rotation RPE per second [deg]; then, for each pair (ground off -> on), the
# decision rule of docs/design/attitude.md section 8: the pooled (RMS over sequences) roll, pitch, ATE rotation and ATE must
# not get worse, no sequence's roll or pitch worse by more than max(0.2 deg, 10 %), no map ATE worse by more than 5 %.
# Each breach is listed. DORADO=path of the CLI (default build/apps/dorado).
import glob, json, os, re, subprocess, sys
import numpy as np
from scipy.spatial.transform import Rotation as R, Slerp

DORADO = os.environ.get('DORADO', 'build/apps/dorado')

def load(p):
    a = np.loadtxt(p, comments='#', ndmin=2)
    return a[:, 0], R.from_quat(a[:, 4:8])

def evaluate(gt, est, extra):
    out = est + '.ground_eval' + ('_'.join(extra) or '') + '.json'
    subprocess.run([DORADO, 'eval', '--gt', gt, '--est', est, *extra, '--json', out], capture_output=True)
    return json.load(open(out))

def metrics(run_dir, seq_dir):
    gt, est = seq_dir + '/true_trajectory.tum', run_dir + '/trajectory.tum'
    te, re_ = load(est)
    tg, rg = load(gt)
    m = (te >= tg[0]) & (te <= tg[-1])
    te, re_ = te[m], re_[m]
    rgi = Slerp(tg, rg)(te)
    err = (rgi[0].inv() * rgi).inv() * (re_[0].inv() * re_)
    ypr = err.as_euler('ZYX', degrees=True)
    rms = lambda v: float(np.sqrt(np.mean(np.square(v))))
    return dict(roll=rms(ypr[:, 2]), pitch=rms(ypr[:, 1]),
                ate_rot=rms(err.magnitude()) * 180 / np.pi,
                ate=evaluate(gt, est, [])['ate_m']['rmse'],
                rpe_s=evaluate(gt, est, ['--delta', '1', '--unit', 's', '--max-gap', '0.5'])['rpe_rotation_deg']['mean'])

out = sys.argv[1]
group = lambda s: re.sub(r'_s\d+$', '', s)
raw = {}
for run_dir in sorted(glob.glob(os.path.join(out, 'runs', '*', '*'))):
    seq, run = run_dir.split(os.sep)[-2:]
    if os.path.exists(run_dir + '/trajectory.tum'):
        raw.setdefault(run, {}).setdefault(group(seq), []).append(metrics(run_dir, os.path.join(out, 'data', seq)))
keys = ['roll', 'pitch', 'ate_rot', 'ate', 'rpe_s']
rows = {run: {g: {k: float(np.mean([x[k] for x in xs])) for k in keys} for g, xs in by.items()} for run, by in raw.items()}
seqs = sorted({g for r in rows.values() for g in r})
print('| sequence | run | seeds | roll RMS deg | pitch RMS deg | ATE rot deg | ATE m | RPE/s rot deg |')
print('|---|---|---|---|---|---|---|---|')
for g in seqs:
    for run in sorted(rows):
        if g in rows[run]:
            x = rows[run][g]
            print(f"| {g} | {run} | {len(raw[run][g])} | {x['roll']:.2f} | {x['pitch']:.2f} | {x['ate_rot']:.2f} | {x['ate']:.3f} | {x['rpe_s']:.3f} |")
print()
pooled = lambda run, k: float(np.sqrt(np.mean([rows[run][g][k] ** 2 for g in rows[run]])))
print('| run (pooled: RMS over sequences) | roll deg | pitch deg | ATE rot deg | ATE m | RPE/s rot deg |')
print('|---|---|---|---|---|---|')
for run in sorted(rows):
    print(f'| {run} | ' + ' | '.join(f'{pooled(run, k):.3f}' for k in keys) + ' |')
pairs = [('odom_doppler@enabled=false', 'odom_doppler@enabled=true', False),
         ('map_doppler', 'map_doppler@new_on', True),
         ('map_doppler@main_off', 'map_doppler@main_on', True)]
for a, b, is_map in pairs:
    if a not in rows or b not in rows:
        continue
    print(f'\n{a} -> {b}:')
    for k in keys:
        print(f'  pooled {k}: {pooled(a, k):.3f} -> {pooled(b, k):.3f}')
    for g in seqs:
        for k in ['roll', 'pitch'] + (['ate'] if is_map else []):
            va, vb = rows[a][g][k], rows[b][g][k]
            limit = va * 0.05 if k == 'ate' else max(0.2, 0.1 * va)
            if vb - va > limit:
                print(f'  BREACH {g} {k}: {va:.3f} -> {vb:.3f} (+{vb - va:.3f} > {limit:.3f})')

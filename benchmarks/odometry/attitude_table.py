# /usr/bin/python3 benchmarks/odometry/attitude_table.py BENCH_OUT [RUN_SUBSTRING]: per sequence and run of a
# `dorado bench` output, the roll / pitch / yaw drift [deg/min] (slope of a line fitted to the Euler ZYX angles of
# R_gt^T R_align R_est, R_align the best constant rotation, against time) and the ATE rotation [deg] (RMS angle of
# R_gt_rel^T R_est_rel, first pose aligned), as a
# markdown table with the ATE [m], then the same pooled (RMS over sequences) per run.
# --by-sequence: sequences named NAME_sK (one per simulator seed) are grouped by NAME: per group and run the mean
# over seeds of |drift|, ATE rotation and ATE, with the standard error of the mean (the noise of the comparison).
import glob, json, os, subprocess, sys
import numpy as np
from scipy.spatial.transform import Rotation as R, Slerp

def load(p):
    a = np.loadtxt(p, comments='#', ndmin=2)
    return a[:, 0], R.from_quat(a[:, 4:8])

def metrics(run_dir, seq_dir):
    te, re = load(run_dir + '/trajectory.tum')
    tg, rg = load(seq_dir + '/true_trajectory.tum')
    m = (te >= tg[0]) & (te <= tg[-1])
    te, re = te[m], re[m]
    rgi = Slerp(tg, rg)(te)
    err = (rgi[0].inv() * rgi).inv() * (re[0].inv() * re)
    ate_rot = float(np.sqrt(np.mean(err.magnitude() ** 2)) * 180 / np.pi)
    # The drift after the best constant rotation (an absolute attitude, as the ground's, is not
    # penalised for the world frame it chose at the start): R_align = argmax trace, on SO(3).
    M = sum((rgi[i] * re[i].inv()).as_matrix() for i in range(len(te)))
    U, _, Vt = np.linalg.svd(M)
    R_align = R.from_matrix(U @ np.diag([1, 1, np.linalg.det(U @ Vt)]) @ Vt)
    ypr = np.unwrap((rgi.inv() * (R_align * re)).as_euler('ZYX'), axis=0) * 180 / np.pi
    t_min = (te - te[0]) / 60.0
    slope = [float(np.polyfit(t_min, ypr[:, k], 1)[0]) for k in range(3)]
    # ATE (translation, SE(3)-aligned) from `dorado eval` (DORADO=path, default build/apps/dorado).
    subprocess.run([os.environ.get('DORADO', 'build/apps/dorado'), 'eval', '--gt', seq_dir + '/true_trajectory.tum',
                    '--est', run_dir + '/trajectory.tum', '--json', run_dir + '/attitude_eval.json'], capture_output=True)
    ate = json.load(open(run_dir + '/attitude_eval.json'))['ate_m']['rmse']
    # The rotation RPE per second (mean over pairs, as dorado bench's results.md).
    subprocess.run([os.environ.get('DORADO', 'build/apps/dorado'), 'eval', '--gt', seq_dir + '/true_trajectory.tum',
                    '--est', run_dir + '/trajectory.tum', '--delta', '1', '--unit', 's', '--max-gap', '0.5',
                    '--json', run_dir + '/attitude_eval_1s.json'], capture_output=True)
    rpe_s = json.load(open(run_dir + '/attitude_eval_1s.json'))['rpe_rotation_deg']['mean']
    return dict(roll=slope[2], pitch=slope[1], yaw=slope[0], ate_rot=ate_rot, ate=ate, rpe_s=rpe_s)

args = [a for a in sys.argv[1:] if a != '--by-sequence']
by_sequence = '--by-sequence' in sys.argv[1:]
out = args[0]
want = args[1] if len(args) > 1 else ''
rows = {}
for run_dir in sorted(glob.glob(os.path.join(out, 'runs', '*', '*'))):
    seq, run = run_dir.split(os.sep)[-2:]
    if want not in run or not os.path.exists(run_dir + '/trajectory.tum'):
        continue
    rows.setdefault(run, {})[seq] = metrics(run_dir, os.path.join(out, 'data', seq))
seqs = sorted({s for r in rows.values() for s in r})
if by_sequence:
    import re
    group = lambda s: re.sub(r'_s\d+$', '', s)
    keys = ['roll', 'pitch', 'yaw', 'ate_rot', 'ate']
    def stat(values):
        v = np.array(values)
        se = v.std(ddof=1) / np.sqrt(len(v)) if len(v) > 1 else float('nan')
        return v.mean(), se
    print('| sequence | run | seeds | abs roll deg/min | abs pitch deg/min | abs yaw deg/min | ATE rot deg | ATE m |')
    print('|---|---|---|---|---|---|---|---|')
    pooled = {}
    for g in sorted({group(s) for s in seqs}):
        for run in sorted(rows):
            xs = [x for s, x in rows[run].items() if group(s) == g]
            if not xs:
                continue
            cells = []
            for k in keys:
                m, se = stat([abs(x[k]) for x in xs])
                cells.append(f'{m:.3f} +- {se:.3f}' if k == 'ate' else f'{m:.2f} +- {se:.2f}')
                pooled.setdefault(run, {}).setdefault(k, []).append(m)
            print(f"| {g} | {run} | {len(xs)} | " + ' | '.join(cells) + ' |')
    print()
    print('| run | roll | pitch | yaw | ATE rot | ATE m |  (RMS over sequences of the seed means)')
    print('|---|---|---|---|---|---|')
    for run in sorted(pooled):
        print(f'| {run} | ' + ' | '.join(f'{np.sqrt(np.mean(np.square(pooled[run][k]))):.3f}' for k in keys) + ' |')
    # Paired: the second run minus the first on the same recordings (seeds), mean +- standard error.
    runs = sorted(rows)
    if len(runs) == 2:
        a, b = runs
        print()
        print(f'Paired difference, {b} minus {a} (same recordings), mean +- standard error over seeds:')
        print()
        print('| sequence | d ATE rot deg | d ATE m | d abs pitch deg/min | d abs roll deg/min | d abs yaw deg/min |')
        print('|---|---|---|---|---|---|')
        for g in sorted({group(s) for s in seqs}):
            common = [s for s in rows[a] if group(s) == g and s in rows[b]]
            cells = []
            for k in ['ate_rot', 'ate', 'pitch', 'roll', 'yaw']:
                m, se = stat([abs(rows[b][s][k]) - abs(rows[a][s][k]) for s in common])
                cells.append(f'{m:+.3f} +- {se:.3f}' if k == 'ate' else f'{m:+.2f} +- {se:.2f}')
            print(f'| {g} | ' + ' | '.join(cells) + ' |')
    sys.exit(0)
print('| sequence | run | roll deg/min | pitch deg/min | yaw deg/min | ATE rot deg | ATE m | RPE/s rot deg |')
print('|---|---|---|---|---|---|---|---|')
for s in seqs:
    for run in sorted(rows):
        if s in rows[run]:
            x = rows[run][s]
            print(f"| {s} | {run} | {x['roll']:+.2f} | {x['pitch']:+.2f} | {x['yaw']:+.2f} | {x['ate_rot']:.2f} | {x['ate']:.3f} | {x['rpe_s']:.3f} |")
print()
print('| run | roll RMS deg/min | pitch RMS deg/min | yaw RMS deg/min | ATE rot RMS deg | ATE RMS m | RPE/s rot RMS deg | worst roll | worst pitch |')
print('|---|---|---|---|---|---|---|---|---|')
for run in sorted(rows):
    v = rows[run].values()
    q = lambda k: float(np.sqrt(np.mean([x[k] ** 2 for x in v])))
    w = lambda k: max(abs(x[k]) for x in v)
    print(f"| {run} | {q('roll'):.2f} | {q('pitch'):.2f} | {q('yaw'):.2f} | {q('ate_rot'):.2f} | {q('ate'):.3f} | {q('rpe_s'):.3f} | {w('roll'):.2f} | {w('pitch'):.2f} |")

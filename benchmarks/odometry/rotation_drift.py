# benchmarks/odometry/rotation_drift.py RUN_DIR SEQ_DIR (DORADO=path/to/dorado): ATE (dorado eval, SE(3)-aligned) + rotation error with the first
# pose aligned (RMSE of the angle of R_gt_rel^T R_est_rel), pitch error final/max, per 500 m.
import json, os, subprocess, sys
import numpy as np
from scipy.spatial.transform import Rotation as R, Slerp
run, seq = sys.argv[1], sys.argv[2]
def load(p):
    a = np.loadtxt(p, comments='#')
    return a[:, 0], a[:, 1:4], R.from_quat(a[:, 4:8])
te, pe, re = load(run + '/trajectory.tum')
tg, pg, rg = load(seq + '/true_trajectory.tum')
m = (te >= tg[0]) & (te <= tg[-1])
te, pe, re = te[m], pe[m], re[m]
rgi = Slerp(tg, rg)(te)
pgi = np.stack([np.interp(te, tg, pg[:, k]) for k in range(3)], 1)
re_rel = re[0].inv() * re
rg_rel = rgi[0].inv() * rgi
err = (rg_rel.inv() * re_rel).magnitude() * 180 / np.pi
pitch_e = re_rel.as_euler('ZYX', degrees=True)[:, 1]
pitch_g = rg_rel.as_euler('ZYX', degrees=True)[:, 1]
dp = pitch_e - pitch_g
# Best constant rotation: R_align = argmax trace(R^T sum R_gt R_est^T) (projection onto SO(3)).
M = sum((rgi[i] * re[i].inv()).as_matrix() for i in range(len(te)))
U, _, Vt = np.linalg.svd(M)
R_align = R.from_matrix(U @ np.diag([1, 1, np.linalg.det(U @ Vt)]) @ Vt)
err_aligned = rgi.inv() * (R_align * re)
ate_rot_aligned = float(np.sqrt(np.mean(err_aligned.magnitude() ** 2)) * 180 / np.pi)
axes = np.sqrt(np.mean(err_aligned.as_euler('ZYX', degrees=True) ** 2, axis=0))
path = np.sum(np.linalg.norm(np.diff(pgi, axis=0), axis=1))
out = subprocess.run([os.environ.get('DORADO', 'build/apps/dorado'), 'eval', '--gt', seq + '/true_trajectory.tum', '--est',
                      run + '/trajectory.tum', '--json', run + '/eval.json'], capture_output=True)
j = json.load(open(run + '/eval.json'))
res = dict(ate_m=j['ate_m']['rmse'], ate_rot_deg=float(np.sqrt(np.mean(err ** 2))),
           pitch_final_deg=float(dp[-1]), pitch_maxabs_deg=float(np.max(np.abs(dp))),
           pitch_per_500m=float(abs(dp[-1]) * 500 / max(path, 1e-9)), path_m=float(path),
           rpe_rot_deg=j['rpe_rotation_deg']['rmse'], ate_rot_aligned_deg=ate_rot_aligned,
           aligned_yaw_deg=float(axes[0]), aligned_pitch_deg=float(axes[1]), aligned_roll_deg=float(axes[2]))
print(json.dumps({k: round(v, 4) for k, v in res.items()}))
json.dump(res, open(run + '/metrics.json', 'w'))

#!/usr/bin/python3
"""Where the vertical-velocity error of the Doppler ego-velocity comes from.

    DORADO=build/apps/dorado /usr/bin/python3 benchmarks/odometry/vz_error_budget.py [--out DIR]
        [--duration S] [--sequences seq04,seq06,seq08,car_urban]

Per sequence (fixed seed), the simulator is run once as described and once with each of its
effects switched off (a sequence YAML with the override, same seed), then `dorado odometry` with
the default settings and with the direction-noise (errors-in-variables) compensation on. Per scan
the error of the sensor velocity in the BASE frame, e = R_base_radar (v_radar_est - v_radar_true),
is compared with true_twist.csv; the script prints the bias (mean) and spread of e_z, and the
pitch-rate bias it becomes through eq. (5), e_z / (m - s_x), in deg/s. A part's share is the change
of the bias when that effect alone is switched off ("all off" = an ideal radar).
"""
import argparse
import os
import subprocess
import sys

import numpy as np
import yaml
from scipy.spatial.transform import Rotation

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
DORADO = os.environ.get('DORADO', os.path.join(ROOT, 'build/apps/dorado'))

# Simulator effects, each switched off alone (radar/terrain overrides of the sequence YAML).
VARIANTS = [
    ('as described', {}),
    ('no direction noise', {'radar': {'azimuth_sigma_deg': 0.0, 'elevation_sigma_deg': 0.0}}),
    ('no ground multipath', {'radar': {'ground_multipath_probability': 0.0}}),
    ('no ghosts/clutter', {'radar': {'ghost_probability': 0.0, 'double_bounce_probability': 0.0,
                                     'clutter_per_scan': 0.0}}),
    ('no ground returns', {'radar': {'ground_returns_per_scan': 0.0}}),
    ('no weak-return noise', {'radar': {'doppler_snr_ref_db': -100.0}}),
    ('no movers', {'dynamic': {'people': 0, 'cars': 0, 'cyclists': 0, 'crowds': 0,
                               'large_vehicles': 0}}),
    ('no roughness', {'terrain': {'roughness_m': 0.0}}),
    ('all off', {'radar': {'azimuth_sigma_deg': 0.0, 'elevation_sigma_deg': 0.0,
                           'ground_multipath_probability': 0.0, 'ghost_probability': 0.0,
                           'double_bounce_probability': 0.0, 'clutter_per_scan': 0.0,
                           'doppler_snr_ref_db': -100.0},
                 'dynamic': {'people': 0, 'cars': 0, 'cyclists': 0, 'crowds': 0,
                             'large_vehicles': 0},
                 'terrain': {'roughness_m': 0.0}}),
]
ESTIMATORS = [('plain eq. 2', None), ('EIV compensated', {'ego_velocity': {
    'compensate_direction_noise': True}})]


def merge(base, override):
    out = dict(base)
    for k, v in override.items():
        out[k] = merge(out.get(k, {}), v) if isinstance(v, dict) else v
    return out


def run(cmd):
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(' '.join(cmd) + ' failed:\n' + r.stderr[-2000:])


def errors(sim_dir, odo_dir):
    ds = yaml.safe_load(open(os.path.join(sim_dir, 'dataset.yaml')))
    q = ds['extrinsics']['T_base_radar']['quaternion_xyzw']
    s = np.array(ds['extrinsics']['T_base_radar']['translation_m'])
    m = ds['vehicle']['half_wheelbase_m']
    R_base_radar = Rotation.from_quat(q).as_matrix()
    est = np.genfromtxt(os.path.join(odo_dir, 'velocities.csv'), delimiter=',', names=True,
                        usecols=(0, 1, 2, 3, 24))
    tru = np.genfromtxt(os.path.join(sim_dir, 'true_twist.csv'), delimiter=',', names=True)
    idx = np.searchsorted(tru['t'], est['t'])
    idx = np.clip(idx, 0, len(tru) - 1)
    ok = (np.abs(tru['t'][idx] - est['t']) < 1e-6) & (est['valid'] == 1)
    v_est = np.stack([est['v_radar_x'], est['v_radar_y'], est['v_radar_z']], 1)[ok]
    v_tru = np.stack([tru['v_radar_x'], tru['v_radar_y'], tru['v_radar_z']], 1)[idx[ok]]
    moving = np.linalg.norm(v_tru, axis=1) > 0.2
    e = ((v_est - v_tru) @ R_base_radar.T)[moving]
    speed = np.linalg.norm(v_tru[moving], axis=1)
    return e[:, 2], speed, m - s[0]


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--out', default='/tmp/vz_error_budget')
    ap.add_argument('--duration', type=float, default=30.0)
    ap.add_argument('--sequences', default='seq04,seq06,seq08,car_urban')
    args = ap.parse_args()
    print('| sequence | simulator | estimator | scans | bias e_z [mm/s] | std e_z [mm/s] | '
          'bias / speed [1e-3] | pitch-rate bias [deg/s] |')
    print('|---|---|---|---|---|---|---|---|')
    for seq in args.sequences.split(','):
        base = yaml.safe_load(open(os.path.join(ROOT, 'configs/sequences', seq + '.yaml')))
        for vname, override in VARIANTS:
            tag = vname.replace(' ', '_').replace('/', '_')
            sim_dir = os.path.join(args.out, seq, tag)
            if not os.path.exists(os.path.join(sim_dir, 'true_twist.csv')):
                os.makedirs(sim_dir, exist_ok=True)
                seq_yaml = os.path.join(args.out, seq, tag + '.yaml')
                yaml.safe_dump(merge(base, override), open(seq_yaml, 'w'))
                run([DORADO, 'simulate', '--sequence', seq_yaml, '--out', sim_dir, '--duration',
                     str(args.duration)])
            estimators = ESTIMATORS if vname in ('as described', 'all off') else ESTIMATORS[:1]
            for ename, cfg in estimators:
                odo_dir = os.path.join(sim_dir, 'odo_' + ('eiv' if cfg else 'plain'))
                cmd = [DORADO, 'odometry', os.path.join(sim_dir, 'dataset.yaml'), '--out', odo_dir, '--accept-implausible']
                if cfg:
                    cfg_path = odo_dir + '.yaml'
                    yaml.safe_dump(cfg, open(cfg_path, 'w'))
                    cmd += ['--config', cfg_path]
                run(cmd)
                ez, speed, lever = errors(sim_dir, odo_dir)
                print(f'| {seq} | {vname} | {ename} | {len(ez)} | {1e3 * ez.mean():+.1f} | '
                      f'{1e3 * ez.std():.1f} | {1e3 * ez.mean() / speed.mean():+.2f} | '
                      f'{np.degrees(ez.mean() / lever):+.3f} |', flush=True)


if __name__ == '__main__':
    main()

#!/usr/bin/python3
"""Scores `dorado odometry` (or `dorado map`) on a real 2D-radar recording against its reference.

    benchmarks/real/score_real.py DATASET.yaml RUN_DIR [--dorado build/apps/dorado] [--labels radarscenes|nuscenes]

RUN_DIR holds trajectory.tum, and for odometry velocities.csv and masks/ (dorado odometry --masks).
Prints one table row: ATE (SE(3) alignment), RPE per second, the end-point error and the KITTI
drift over 100-800 m (all four from `dorado eval`), the base velocity and yaw-rate RMSE per scan against the reference
differentiated (central differences of the reference's poses at the scan times), and the dynamic
mask's precision and recall for moving points, judged two ways:
  - by label: RadarScenes label != 11 (a class of road user, also when parked); nuScenes dyn_prop
    in {0 moving, 2 oncoming, 6 crossing moving} vs {1, 3, 5, 7} (4 unknown left out);
  - by reference: |v_r + d . v_radar_ref| > 0.5 m/s, the Doppler the reference's own motion does not
    explain (a parked car is static here).
Points the estimator filtered out (mask label 2) are left out of both.
"""
import argparse
import json
import os
import subprocess
import sys
import tempfile

import numpy as np
import yaml

MOVING_THRESHOLD_MPS = 0.5


def read_tum(path):
    a = np.loadtxt(path, comments="#", ndmin=2)
    yaw = 2.0 * np.arctan2(a[:, 6], a[:, 7])  # planar: qz, qw (roll = pitch = 0)
    return a[:, 0], a[:, 1:3], np.unwrap(yaw)


def reference_twist(t_ref, p_ref, yaw_ref, t):
    """Base velocity (x, y in the base frame) and yaw rate of the reference at times t."""
    v_world = np.gradient(p_ref, t_ref, axis=0)
    yaw_rate = np.gradient(yaw_ref, t_ref)
    vx = np.interp(t, t_ref, v_world[:, 0])
    vy = np.interp(t, t_ref, v_world[:, 1])
    yaw = np.interp(t, t_ref, yaw_ref)
    c, s = np.cos(yaw), np.sin(yaw)
    return np.stack([c * vx + s * vy, -s * vx + c * vy], axis=1), np.interp(t, t_ref, yaw_rate)


def mount(config):
    T = config["extrinsics"]["T_base_radar"]
    x, y = T["translation_m"][:2]
    if "quaternion_xyzw" in T:
        q = T["quaternion_xyzw"]
        yaw = 2.0 * np.arctan2(q[2], q[3])
    else:
        yaw = np.radians(T["rotation_rpy_deg"][2])
    return np.array([x, y]), yaw


def dorado_eval(dorado, gt, est):
    with tempfile.TemporaryDirectory() as tmp:
        out = os.path.join(tmp, "eval.json")
        subprocess.run([dorado, "eval", "--gt", gt, "--est", est, "--delta", "1", "--unit",
                        "seconds", "--json", out], check=True, stdout=subprocess.DEVNULL)
        with open(out) as f:
            return json.load(f)


def data_path(config_dir, config, path):
    """A description's path as dorado resolves it without --data: from its data_dir:, else its folder."""
    return os.path.join(config_dir, config.get("data_dir") or ".", path)


def mask_scores(config_dir, config, run_dir, labels_kind, t_scans, v_radar_ref):
    folder = config["folder"]
    scans_dir = data_path(config_dir, config, folder["scans_dir"])
    files = sorted(f for f in os.listdir(scans_dir) if f.endswith(".bin"))
    counts = {"label": np.zeros(4), "reference": np.zeros(4)}  # tp fp fn tn
    for k, name in enumerate(files):
        mask_path = os.path.join(run_dir, "masks", "%06d.txt" % k)
        if not os.path.exists(mask_path) or k >= len(v_radar_ref):
            continue
        pred = np.loadtxt(mask_path, comments="#", dtype=int, ndmin=1)
        pts = np.fromfile(os.path.join(scans_dir, name), dtype=np.float32).reshape(-1, 6)
        if len(pred) != len(pts):
            sys.exit("%s: %d labels for %d points" % (mask_path, len(pred), len(pts)))
        used = pred != 2
        moving_pred = pred == 1
        label = pts[:, 5].astype(int)
        if labels_kind == "radarscenes":
            truth_label, known = label != 11, np.ones(len(label), bool)
        else:
            truth_label, known = np.isin(label, [0, 2, 6]), label != 4
        d = pts[:, :2] / np.linalg.norm(pts[:, :2], axis=1, keepdims=True)
        truth_ref = np.abs(pts[:, 4] + d @ v_radar_ref[k]) > MOVING_THRESHOLD_MPS
        for key, truth, sel in (("label", truth_label, used & known), ("reference", truth_ref, used)):
            p, t = moving_pred[sel], truth[sel]
            counts[key] += [np.sum(p & t), np.sum(p & ~t), np.sum(~p & t), np.sum(~p & ~t)]
    out = {}
    for key, (tp, fp, fn, tn) in counts.items():
        out[key] = (tp / max(tp + fp, 1), tp / max(tp + fn, 1), int(tp + fn))
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dataset")
    ap.add_argument("run_dir")
    ap.add_argument("--dorado", default="build/apps/dorado")
    ap.add_argument("--labels", choices=["radarscenes", "nuscenes"], default="radarscenes")
    ap.add_argument("--name", default="")
    ap.add_argument("--header", action="store_true")
    args = ap.parse_args()
    config_dir = os.path.dirname(os.path.abspath(args.dataset))
    with open(args.dataset) as f:
        config = yaml.safe_load(f)
    gt = data_path(config_dir, config, config["ground_truth"]["path"])
    est = os.path.join(args.run_dir, "trajectory.tum")
    ev = dorado_eval(args.dorado, gt, est)
    t_ref, p_ref, yaw_ref = read_tum(gt)
    end = ev["end_point_error"]  # start poses aligned; % of the reference's path
    row = {"ate_m": ev["ate_m"]["rmse"], "rpe_t_m": ev["rpe_translation_m"]["rmse"],
           "rpe_r_deg": ev["rpe_rotation_deg"]["rmse"], "path_m": end["path_length_m"],
           "end_pct": end["percent"], "end_m": end["error_m"]}
    drift = ev.get("kitti_drift", {})
    row["drift_pct"] = drift.get("translation_percent", float("nan"))
    row["drift_deg100"] = drift.get("rotation_deg_per_100m", float("nan"))
    vel_path = os.path.join(args.run_dir, "velocities.csv")
    if os.path.exists(vel_path):
        v = np.genfromtxt(vel_path, delimiter=",", names=True, dtype=None, encoding=None)
        t = np.asarray(v["t"], float)
        v_ref, w_ref = reference_twist(t_ref, p_ref, yaw_ref, t)
        valid = np.asarray(v["valid"]) == 1
        ev_x = np.asarray(v["v_base_x"], float) - v_ref[:, 0]
        ev_y = np.asarray(v["v_base_y"], float) - v_ref[:, 1]
        ew = np.asarray(v["omega_base_z"], float) - w_ref
        row["valid"] = "%d/%d" % (valid.sum(), len(valid))
        row["v_rmse"] = np.sqrt(np.mean(ev_x[valid] ** 2 + ev_y[valid] ** 2))
        row["w_rmse_dps"] = np.degrees(np.sqrt(np.mean(ew[valid] ** 2)))
        # The reference's radar velocity (for the mask judged by the reference).
        s, yaw_m = mount(config)
        vs = v_ref + w_ref[:, None] * np.stack([-s[1] * np.ones_like(t), s[0] * np.ones_like(t)], 1)
        c, sn = np.cos(yaw_m), np.sin(yaw_m)
        v_radar_ref = np.stack([c * vs[:, 0] + sn * vs[:, 1], -sn * vs[:, 0] + c * vs[:, 1]], 1)
        if os.path.isdir(os.path.join(args.run_dir, "masks")):
            m = mask_scores(config_dir, config, args.run_dir, args.labels, t, v_radar_ref)
            row["mask_label"] = "%.3f / %.3f" % m["label"][:2]
            row["mask_ref"] = "%.3f / %.3f" % m["reference"][:2]
    twist_path = os.path.join(args.run_dir, "twist.csv")
    if os.path.exists(twist_path):  # dorado twist: the joint twist and the first radar's kinematic one
        v = np.genfromtxt(twist_path, delimiter=",", names=True)
        t = v["t"]
        v_ref, w_ref = reference_twist(t_ref, p_ref, yaw_ref, t)
        ok = v["valid"] == 1
        row["valid"] = "%d/%d" % (ok.sum(), len(ok))
        row["v_rmse"] = np.sqrt(np.mean((v["v_x"] - v_ref[:, 0])[ok] ** 2 + (v["v_y"] - v_ref[:, 1])[ok] ** 2))
        row["w_rmse_dps"] = np.degrees(np.sqrt(np.mean((v["omega_z"] - w_ref)[ok] ** 2)))
        kin = v["kinematic_valid"] == 1
        row["w_rmse_kin_dps"] = np.degrees(np.sqrt(np.mean((v["kinematic_omega_z"] - w_ref)[kin] ** 2)))
        both = ok & kin
        row["w_rmse_pair"] = "%.3f / %.3f (%d)" % (
            np.degrees(np.sqrt(np.mean((v["omega_z"] - w_ref)[both] ** 2))),
            np.degrees(np.sqrt(np.mean((v["kinematic_omega_z"] - w_ref)[both] ** 2))), both.sum())
    cols = ["path_m", "valid", "ate_m", "rpe_t_m", "rpe_r_deg", "drift_pct", "drift_deg100", "end_pct", "end_m",
            "v_rmse", "w_rmse_dps", "mask_label", "mask_ref"]
    heads = ["path [m]", "valid", "ATE [m]", "RPE 1 s [m]", "RPE 1 s [deg]", "drift [%]",
             "drift [deg/100 m]", "end [% path]", "end [m]", "v RMSE [m/s]", "yaw rate RMSE [deg/s]",
             "moving P / R (label)", "moving P / R (reference)"]
    # dorado twist only (else "-"): one column set for every run, so that rows of runs of both kinds
    # make one table.
    cols.append("w_rmse_pair")
    heads.append("twist: yaw rate RMSE joint / kinematic, same scans [deg/s]")
    if args.header:
        print("| run | " + " | ".join(heads) + " |")
        print("|---|" + "---:|" * len(heads))
    fmt = lambda x: ("%.3f" % x) if isinstance(x, float) else str(x)
    print("| %s | " % (args.name or args.run_dir) + " | ".join(fmt(row.get(c, "-")) for c in cols) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Paper-style figures of a `dorado bench` output directory (Figs. 4-7 of the Doppler odometry paper,
and the mapper's runtime per stage), as PNG and PDF in OUT/plots/.

Usage: /usr/bin/python3 scripts/plot_benchmark.py OUT

Reads OUT/rpe_pairs.csv (written by dorado bench), OUT/data/<seq>/ground_truth.tum or the ground truth
named in OUT/bench_runs.csv, and each run's files under OUT/runs/<seq>/<method>/ (trajectory.tum,
velocities.csv, scans.csv). A figure whose inputs are missing is skipped with a note on stderr.
"""
import csv
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ODOM_METHODS = ["odom_imu", "odom_doppler", "odom_imu+doppler"]
MAP_METHODS = ["map_none", "map_constvel", "map_imu", "map_doppler", "map_imu+doppler"]
LABELS = {"odom_imu": "IMU", "odom_doppler": "Doppler", "odom_imu+doppler": "IMU + Doppler",
          "map_none": "NP", "map_constvel": "CV", "map_imu": "IMU", "map_doppler": "Dopp",
          "map_imu+doppler": "I+D"}
COLORS = {"odom_imu": "tab:blue", "odom_doppler": "tab:orange", "odom_imu+doppler": "tab:green",
          "map_none": "tab:red", "map_constvel": "tab:purple", "map_imu": "tab:blue",
          "map_doppler": "tab:orange", "map_imu+doppler": "tab:green"}


def note(message):
    print("plot_benchmark: " + message, file=sys.stderr)


def save(fig, out_dir, name):
    os.makedirs(os.path.join(out_dir, "plots"), exist_ok=True)
    for ext in ("png", "pdf"):
        fig.savefig(os.path.join(out_dir, "plots", name + "." + ext), dpi=150, bbox_inches="tight")
    plt.close(fig)


def read_csv(path):
    if not os.path.exists(path):
        return None
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def column(rows, name):
    out = []
    for r in rows:
        try:
            out.append(float(r.get(name, "nan")))
        except (TypeError, ValueError):
            out.append(float("nan"))
    return np.array(out)


def read_tum(path):
    if not os.path.exists(path):
        return None
    data = []
    with open(path) as f:
        for line in f:
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            data.append([float(x) for x in line.split()[:8]])
    return np.array(data) if data else None


def quat_to_rot(q):
    x, y, z, w = q
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def sequences_and_methods(pairs):
    seqs, methods = [], []
    for r in pairs:
        if r["sequence"] not in seqs:
            seqs.append(r["sequence"])
        if r["method"] not in methods:
            methods.append(r["method"])
    return seqs, methods


def boxplot_grid(out_dir, pairs, methods, delta_unit, name, title, label_outliers):
    """One row per quantity (translation, rotation); per sequence a group of boxes, one per method."""
    seqs, present = sequences_and_methods(pairs)
    methods = [m for m in methods if m in present]
    if not methods:
        note("no runs for " + name + ", skipped")
        return
    quantities = [("translation_m", "translation [m]"), ("rotation_deg", "rotation [deg]")]
    fig, axes = plt.subplots(len(quantities), 1, figsize=(max(6, 1.6 * len(seqs) * len(methods) / 3), 6.5),
                             squeeze=False)
    width = 0.8 / len(methods)
    for row, (key, ylabel) in enumerate(quantities):
        ax = axes[row][0]
        all_values = []
        boxes = []  # (position, values) of every box, to label those reaching above the axis
        for mi, method in enumerate(methods):
            data, positions = [], []
            for si, seq in enumerate(seqs):
                values = np.array([float(r[key]) for r in pairs
                                   if r["sequence"] == seq and r["method"] == method
                                   and r["delta_unit"] == delta_unit])
                values = values[np.isfinite(values)]
                if values.size == 0:
                    continue
                data.append(values)
                positions.append(si + (mi - (len(methods) - 1) / 2) * width)
                all_values.extend(values.tolist())
            if not data:
                continue
            bp = ax.boxplot(data, positions=positions, widths=width * 0.85, patch_artist=True,
                            showfliers=not label_outliers, flierprops={"markersize": 2})
            for box in bp["boxes"]:
                box.set_facecolor(COLORS.get(method, "gray"))
                box.set_alpha(0.75)
            ax.plot([], [], color=COLORS.get(method, "gray"), lw=6, label=LABELS.get(method, method))
            boxes.extend(zip(positions, data))
        if label_outliers and all_values:
            # The axis shows the bulk of the boxes; a box reaching above it gets its maximum written.
            q3s = [np.percentile(v, 75) + 1.5 * (np.percentile(v, 75) - np.percentile(v, 25))
                   for _, v in boxes]
            top = max(np.median(q3s) * 1.6, 1e-9) if q3s else max(all_values)
            ax.set_ylim(0, top)
            for pos, values in boxes:
                if values.max() > top:
                    ax.annotate(f"{values.max():.2g}", (pos, top), xytext=(0, -2), textcoords="offset points",
                                ha="center", va="top", fontsize=7, rotation=90)
        ax.set_xticks(range(len(seqs)))
        ax.set_xticklabels(seqs)
        ax.set_ylabel(ylabel)
        ax.grid(axis="y", alpha=0.3)
        if row == 0:
            # Above the axes, so that it hides no box or label.
            ax.legend(ncol=len(methods), fontsize=8, loc="lower left", bbox_to_anchor=(0, 1.0),
                      frameon=False)
            ax.set_title(title, pad=22)
    save(fig, out_dir, name)


def fig4_angular_velocity(out_dir, seqs):
    """Angular velocity from Doppler against the IMU gyro over time, per axis (paper Fig. 4)."""
    candidates = [s for s in ["seq11"] + seqs if os.path.exists(
        os.path.join(out_dir, "runs", s, "odom_doppler", "velocities.csv"))]
    if not candidates:
        note("no odom_doppler/velocities.csv, Fig. 4 skipped")
        return
    seq = candidates[0]
    rows = read_csv(os.path.join(out_dir, "runs", seq, "odom_doppler", "velocities.csv"))
    if not rows:
        note("empty velocities.csv, Fig. 4 skipped")
        return
    t = column(rows, "t")
    t = t - t[np.isfinite(t)][0]
    fig, axes = plt.subplots(3, 1, figsize=(8, 6), sharex=True)
    for ax, axis, name in zip(axes, "xyz", ["roll rate", "pitch rate", "yaw rate"]):
        doppler = column(rows, "omega_base_" + axis)
        gyro = column(rows, "gyro_base_" + axis)
        if np.isfinite(gyro).any():
            ax.plot(t, gyro, color="tab:blue", lw=0.8, label="IMU")
        ax.plot(t, doppler, color="tab:orange", lw=0.8, label="Doppler")
        ax.set_ylabel(name + " [rad/s]")
        ax.grid(alpha=0.3)
    axes[0].legend(ncol=2, fontsize=8)
    axes[0].set_title("Angular velocity from Doppler against the IMU, " + seq)
    axes[-1].set_xlabel("time [s]")
    save(fig, out_dir, "fig4_angular_velocity")


def ground_truth_path(out_dir, seq):
    rows = read_csv(os.path.join(out_dir, "bench_runs.csv")) or []
    for r in rows:
        if r["sequence"] == seq and r.get("ground_truth"):
            return r["ground_truth"]
    return os.path.join(out_dir, "data", seq, "ground_truth.tum")


def close_view(centre, half):
    """(xlim, ylim) of a square view of half-width `half` [m] around centre (x, y)."""
    return (centre[0] - half, centre[0] + half), (centre[1] - half, centre[1] + half)


def fig7_insets(gt, estimates):
    """The close views of Fig. 7, each showing what it names: `start` around the ground truth
    where the estimates start, `end` around the ground truth where they end, both about a tenth
    of the drive across. The end view widens to hold an estimate's end up to 3 of its half-widths
    away; an end farther out is listed (an estimate that drifted off) instead of zooming out to
    the whole drive. gt: TUM rows (t x y ...); estimates: {label: (first_t, last_t, end_xy)}.
    Returns {"start": (xlim, ylim), "end": (xlim, ylim), "off_view": [labels]}."""
    half = max(np.ptp(gt[:, 1]), np.ptp(gt[:, 2]), 1.0) * 0.08
    def gt_at(t):
        k = int(np.argmin(np.abs(gt[:, 0] - t)))
        return gt[k, 1:3]
    first_t = min(v[0] for v in estimates.values())
    last_t = max(v[1] for v in estimates.values())
    start, end = gt_at(first_t), gt_at(last_t)
    distances = {label: float(np.linalg.norm(np.asarray(v[2]) - end)) for label, v in estimates.items()}
    near = [d for d in distances.values() if d <= 3 * half]
    end_half = max([half] + [1.1 * d for d in near])
    off_view = sorted(label for label, d in distances.items() if d > 3 * half)
    return {"start": close_view(start, half), "end": close_view(end, end_half), "off_view": off_view}


def fig7_trajectories(out_dir, seqs):
    """Mapper trajectories from above per prior against the ground truth, with close views of the
    start and the end (paper Fig. 7, fig7_insets). Each estimate is put in the ground truth's frame
    by its first pose, so the drift shows as it accumulates."""
    candidates = [s for s in ["seq07"] + seqs if any(os.path.exists(
        os.path.join(out_dir, "runs", s, m, "trajectory.tum")) for m in MAP_METHODS)]
    if not candidates:
        note("no mapper trajectories, Fig. 7 skipped")
        return
    seq = candidates[0]
    gt = read_tum(ground_truth_path(out_dir, seq))
    if gt is None:
        note("no ground truth for " + seq + ", Fig. 7 skipped")
        return
    fig = plt.figure(figsize=(11, 6))
    ax_main = fig.add_subplot(1, 2, 1)
    ax_start = fig.add_subplot(2, 2, 2)
    ax_end = fig.add_subplot(2, 2, 4)
    for ax in (ax_main, ax_start, ax_end):
        ax.plot(gt[:, 1], gt[:, 2], color="black", lw=1.5, label="ground truth")
    estimates = {}
    for method in MAP_METHODS:
        est = read_tum(os.path.join(out_dir, "runs", seq, method, "trajectory.tum"))
        if est is None:
            continue
        k = int(np.argmin(np.abs(gt[:, 0] - est[0, 0])))
        R_gt, R_est = quat_to_rot(gt[k, 4:8]), quat_to_rot(est[0, 4:8])
        R = R_gt @ R_est.T
        p = (R @ (est[:, 1:4] - est[0, 1:4]).T).T + gt[k, 1:4]
        for ax in (ax_main, ax_start, ax_end):
            ax.plot(p[:, 0], p[:, 1], color=COLORS[method], lw=1, label=LABELS[method])
        estimates[LABELS[method]] = (est[0, 0], est[-1, 0], p[-1, :2])
    if not estimates:
        note("no mapper trajectory of " + seq + " could be read, Fig. 7 skipped")
        plt.close(fig)
        return
    views = fig7_insets(gt, estimates)
    for ax, name in ((ax_start, "start"), (ax_end, "end")):
        ax.set_xlim(*views[name][0])
        ax.set_ylim(*views[name][1])
    ax_main.set_title("Mapper trajectory per prior, " + seq)
    ax_start.set_title("start", fontsize=9)
    off = ", ".join(views["off_view"])
    ax_end.set_title("end" + (" (" + off + " ended outside this view)" if off else ""), fontsize=9)
    for ax in (ax_main, ax_start, ax_end):
        ax.set_aspect("equal", adjustable="box")
        ax.grid(alpha=0.3)
    ax_main.set_xlabel("x [m]")
    ax_main.set_ylabel("y [m]")
    ax_main.legend(fontsize=8)
    save(fig, out_dir, "fig7_trajectories")


def runtime_per_stage(out_dir, seqs):
    """Mean time per scan of each mapper stage per prior (stacked), and of the odometry."""
    bars = {}
    for method in MAP_METHODS:
        stage_sums = {}
        for seq in seqs:
            rows = read_csv(os.path.join(out_dir, "runs", seq, method, "scans.csv"))
            if not rows:
                continue
            for key in rows[0].keys():
                if key and key.startswith("time_") and key.endswith("_ms") and key != "time_total_ms":
                    stage_sums.setdefault(key[5:-3], []).extend(column(rows, key).tolist())
        if stage_sums:
            bars[method] = {k: float(np.nanmean(v)) for k, v in stage_sums.items()}
    odom = {}
    for method in ODOM_METHODS:
        values = []
        for seq in seqs:
            rows = read_csv(os.path.join(out_dir, "runs", seq, method, "velocities.csv"))
            if rows:
                values.extend(column(rows, "time_ms").tolist())
        if values and np.isfinite(values).any():
            odom[method] = float(np.nanmean(values))
    if not bars and not odom:
        note("no per-scan timings, runtime figure skipped")
        return
    fig, ax = plt.subplots(figsize=(8, 4))
    names = list(odom.keys()) + list(bars.keys())
    stages = sorted({s for b in bars.values() for s in b})
    cmap = plt.get_cmap("tab10")
    for i, m in enumerate(odom):
        ax.bar(i, odom[m], color="gray")
    bottom = np.zeros(len(bars))
    for si, stage in enumerate(stages):
        heights = np.array([bars[m].get(stage, 0.0) for m in bars])
        heights = np.nan_to_num(heights)
        ax.bar(np.arange(len(odom), len(names)), heights, bottom=bottom, color=cmap(si % 10), label=stage)
        bottom += heights
    ax.set_xticks(range(len(names)))
    ax.set_xticklabels([("odom " if m.startswith("odom") else "map ") + LABELS.get(m, m) for m in names],
                       rotation=30, ha="right")
    ax.set_ylabel("time per scan [ms]")
    ax.set_title("Runtime per scan (mean over sequences; mapper split by stage)")
    ax.grid(axis="y", alpha=0.3)
    if stages:
        ax.legend(fontsize=8)
    save(fig, out_dir, "runtime_per_stage")


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out_dir = sys.argv[1]
    pairs = read_csv(os.path.join(out_dir, "rpe_pairs.csv"))
    if pairs is None:
        note(os.path.join(out_dir, "rpe_pairs.csv") + ": missing (run dorado bench first)")
        return 1
    seqs, _ = sequences_and_methods(pairs)
    fig4_angular_velocity(out_dir, seqs)
    boxplot_grid(out_dir, pairs, ODOM_METHODS, "frames", "fig5_rpe_per_frame",
                 "RPE per frame: odometry", label_outliers=False)
    boxplot_grid(out_dir, pairs, MAP_METHODS, "seconds", "fig6_rpe_per_second",
                 "RPE per second: mapper per prior", label_outliers=True)
    fig7_trajectories(out_dir, seqs)
    runtime_per_stage(out_dir, seqs)
    return 0


if __name__ == "__main__":
    sys.exit(main())

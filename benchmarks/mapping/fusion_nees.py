#!/usr/bin/env python3
"""Scores the mapper's three estimates of each scan's motion (the prior alone, the registration
alone and the smoother's written pose, `fused`, from `dorado map`'s covariance.csv: one row per
written pose) against the exact trajectory, and the consistency of their covariances by NEES.

    fusion_nees.py --truth DATA/true_trajectory.tum --run MAPDIR [--name NAME] ...   (pairs repeat)
    fusion_nees.py ... --check-fused-nees LO HI    exit 1 unless every run's fused 1-frame mean NEES
                                                    lies in [LO, HI] (a test's gate)
    fusion_nees.py ... --check-block-nees LO HI [LO_ROT HI_ROT]
                                                    the same per 3-dof block (translation, rotation;
                                                    a second pair is the rotation's own band)
    fusion_nees.py ... --fused-covariance prior    score the fused pose with the prior's (or the
                                                    registration's) covariance: what a mapper that
                                                    reported that one would be scored (a test's mutation)

Per scan k (both k-1 and k registered), with T_{k-1} the mapper's previous written (fused) pose, the
motion of source X is D_X = T_{k-1}^-1 T_X,k and its error xi = Log(D_X^-1 D_true) (right
perturbation in the base frame, the convention of the covariances). NEES = xi^T C_X^-1 xi with
6 degrees of freedom. Over 1 s (the frames of one second at the run's median scan interval), the fused per-frame covariances are compounded (independent steps)
and compared with the error of T_{k-n}^-1 T_k. The chi-square 95 % band of a mean over N samples
is [chi2(0.025, 6N) / N, chi2(0.975, 6N) / N] (Wilson-Hilferty); the per-sample band is
[1.24, 14.45]. Samples of one drive are correlated, so the mean's band is a strict reading.
"""
import argparse
import bisect
import csv
import math
import sys

import numpy as np

AXES = ["x", "y", "z", "rx", "ry", "rz"]


def hat(v):
    return np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])


def quat_to_rot(qx, qy, qz, qw):
    n = math.sqrt(qx * qx + qy * qy + qz * qz + qw * qw)
    x, y, z, w = qx / n, qy / n, qz / n, qw / n
    return np.array([
        [1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
        [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
        [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pose(values):
    T = np.eye(4)
    T[:3, :3] = quat_to_rot(*values[3:7])
    T[:3, 3] = values[:3]
    return T


def inv(T):
    Ti = np.eye(4)
    Ti[:3, :3] = T[:3, :3].T
    Ti[:3, 3] = -T[:3, :3].T @ T[:3, 3]
    return Ti


def log_so3(R):
    c = max(-1.0, min(1.0, (np.trace(R) - 1) / 2))
    theta = math.acos(c)
    w = np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])
    if theta < 1e-9:
        return 0.5 * w
    return theta / (2 * math.sin(theta)) * w


def exp_so3(phi):
    theta = np.linalg.norm(phi)
    A = hat(phi)
    if theta < 1e-12:
        return np.eye(3) + A
    return np.eye(3) + math.sin(theta) / theta * A + (1 - math.cos(theta)) / theta**2 * A @ A


def log_se3(T):
    phi = log_so3(T[:3, :3])
    theta = np.linalg.norm(phi)
    A = hat(phi)
    if theta < 1e-9:
        V_inv = np.eye(3) - 0.5 * A
    else:
        V_inv = np.eye(3) - 0.5 * A + (1 / theta**2) * (
            1 - (theta * math.sin(theta)) / (2 * (1 - math.cos(theta)))) * A @ A
    return np.concatenate([V_inv @ T[:3, 3], phi])


def adjoint(T):
    Ad = np.zeros((6, 6))
    R, t = T[:3, :3], T[:3, 3]
    Ad[:3, :3] = R
    Ad[:3, 3:] = hat(t) @ R
    Ad[3:, 3:] = R
    return Ad


def chi2_quantile(p, k):
    z = {0.025: -1.959964, 0.975: 1.959964}[p]
    return k * (1 - 2 / (9 * k) + z * math.sqrt(2 / (9 * k)))**3


class Truth:
    """The exact poses, interpolated at a scan's stamp (as `dorado bench` does)."""

    def __init__(self, path):
        self.t, self.T = [], []
        with open(path) as f:
            for line in f:
                if line.startswith("#") or not line.strip():
                    continue
                v = [float(x) for x in line.split()]
                self.t.append(v[0])
                self.T.append(pose(v[1:8]))

    def at(self, t):
        """Interpolated (translation linearly, rotation on the geodesic) within a 0.5 s gap."""
        i = bisect.bisect_right(self.t, t)
        if i == 0 or i == len(self.t):
            return self.T[i - 1] if i == len(self.t) and abs(self.t[-1] - t) < 1e-6 else None
        t0, t1 = self.t[i - 1], self.t[i]
        if t1 - t0 > 0.5:
            return None
        a = (t - t0) / (t1 - t0)
        T0, T1 = self.T[i - 1], self.T[i]
        T = np.eye(4)
        T[:3, :3] = T0[:3, :3] @ exp_so3(a * log_so3(T0[:3, :3].T @ T1[:3, :3]))
        T[:3, 3] = (1 - a) * T0[:3, 3] + a * T1[:3, 3]
        return T


def read_covariance_csv(path, scale=1.0):
    rows = []
    with open(path) as f:
        for row in csv.DictReader(f):
            entry = {"t": float(row["t"]), "status": row["status"]}
            for source in ("fused", "registration", "prior"):
                if row[source + "_x"] == "":
                    continue
                T = pose([float(row[f"{source}_{p}"]) for p in ("x", "y", "z", "qx", "qy", "qz", "qw")])
                C = np.zeros((6, 6))
                for i in range(6):
                    for j in range(i, 6):
                        C[i, j] = C[j, i] = float(row[f"{source}_c_{AXES[i]}_{AXES[j]}"])
                entry[source] = (T, scale * C)
            rows.append(entry)
    return rows


def nees(xi, C):
    try:
        return float(xi @ np.linalg.solve(C, xi))
    except np.linalg.LinAlgError:
        return float("inf")


def score(truth, rows, second_frames, fused_covariance="fused"):
    sources = ("prior", "registration", "fused")
    err = {s: [] for s in sources}
    ne = {s: [] for s in sources}
    ne_1s = []
    ne_block = {"trans": [], "rot": []}
    true_poses = [truth.at(r["t"]) for r in rows]
    for k in range(1, len(rows)):
        prev, cur = rows[k - 1], rows[k]
        if cur["status"] != "fused" or true_poses[k - 1] is None or true_poses[k] is None:
            continue
        T_prev = prev["fused"][0]
        D_true = inv(true_poses[k - 1]) @ true_poses[k]
        if fused_covariance not in cur:
            continue
        for s in sources:
            if s not in cur:
                continue
            T, C = cur[s]
            if s == "fused":
                C = cur[fused_covariance][1]
            xi = log_se3(inv(inv(T_prev) @ T) @ D_true)
            err[s].append(xi)
            ne[s].append(nees(xi, C))
            if s == "fused":
                ne_block["trans"].append(nees(xi[:3], C[:3, :3]))
                ne_block["rot"].append(nees(xi[3:], C[3:, 3:]))
        n = second_frames
        if k >= n and all(rows[i]["status"] == "fused" for i in range(k - n + 1, k + 1)) \
                and true_poses[k - n] is not None:
            T_k = cur["fused"][0]
            C_sum = np.zeros((6, 6))
            for i in range(k - n + 1, k + 1):
                T_i, C_i = rows[i]["fused"]
                Ad = adjoint(inv(inv(T_i) @ T_k))
                C_sum += Ad @ C_i @ Ad.T
            D_est = inv(rows[k - n]["fused"][0]) @ T_k
            D_true_n = inv(true_poses[k - n]) @ true_poses[k]
            ne_1s.append(nees(log_se3(inv(D_est) @ D_true_n), C_sum))
    return err, ne, ne_1s, ne_block


def scan_rate_hz(rows):
    """Frames per second of a run: 1 / its median interval between scans (15 Hz data has 15)."""
    intervals = np.diff([r["t"] for r in rows])
    intervals = intervals[intervals > 0]
    return 1.0 / float(np.median(intervals)) if len(intervals) else 10.0


def rmse(errors, part):
    if not errors:
        return float("nan")
    e = np.array(errors)[:, part]
    return math.sqrt(np.mean(np.sum(e * e, axis=1)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--truth", action="append", required=True, help="true_trajectory.tum (exact)")
    ap.add_argument("--run", action="append", required=True, help="dorado map output folder")
    ap.add_argument("--name", action="append", help="a label per run")
    ap.add_argument("--scan-rate-hz", type=float, default=None,
                    help="frames per second for the 1 s NEES (default: each run's median scan interval)")
    ap.add_argument("--check-fused-nees", nargs=2, type=float, metavar=("LO", "HI"))
    ap.add_argument("--check-block-nees", nargs="+", type=float, metavar="LO HI [LO_ROT HI_ROT]",
                    help="the fused 1-frame mean NEES of each 3-dof block (translation, rotation); "
                         "a second pair is the rotation's band")
    ap.add_argument("--fused-covariance", choices=("fused", "prior", "registration"), default="fused",
                    help="the covariance the fused pose is scored with (a test's mutation)")
    ap.add_argument("--scale-covariance", type=float, default=1.0,
                    help="multiply every covariance read (a test shows that a wrong scale fails the gate)")
    args = ap.parse_args()
    block_bands = []
    if args.check_block_nees:
        if len(args.check_block_nees) not in (2, 4):
            sys.exit("fusion_nees.py: --check-block-nees takes LO HI or LO HI LO_ROT HI_ROT")
        b = args.check_block_nees
        block_bands = [(b[0], b[1]), (b[-2], b[-1])]
    if len(args.truth) != len(args.run):
        sys.exit("fusion_nees.py: give one --truth per --run")
    names = args.name or [r.rstrip("/").split("/")[-1] for r in args.run]
    print("| sequence | frames | per-frame trans [mm] prior / reg / fused | per-frame rot [deg] prior / reg / fused "
          "| mean NEES 1 frame prior / reg / fused | fused NEES in 95 % per-sample band | mean NEES 1 s (fused) "
          "| mean's 95 % band (1 frame) | mean NEES 1 frame fused trans / rot (3 dof) |")
    print("|---|---:|---|---|---|---:|---:|---|---|")
    ok = True
    for truth_path, run, name in zip(args.truth, args.run, names):
        truth = Truth(truth_path)
        rows = read_covariance_csv(run.rstrip("/") + "/covariance.csv", args.scale_covariance)
        rate_hz = args.scan_rate_hz or scan_rate_hz(rows)
        err, ne, ne_1s, ne_block = score(truth, rows, max(1, int(round(rate_hz))), args.fused_covariance)
        N = len(ne["fused"])
        if N == 0:
            print(f"| {name} | 0 | no fused scans matched the truth's stamps |")
            ok = False
            continue
        band = (chi2_quantile(0.025, 6 * N) / N, chi2_quantile(0.975, 6 * N) / N)
        inside = np.mean([(1.237 <= v <= 14.449) for v in ne["fused"]])
        tr = " / ".join(f"{1000 * rmse(err[s], slice(0, 3)):.1f}" for s in ("prior", "registration", "fused"))
        rot = " / ".join(f"{math.degrees(rmse(err[s], slice(3, 6))):.3f}" for s in ("prior", "registration", "fused"))
        nm = " / ".join(f"{np.mean(ne[s]):.2f}" if ne[s] else "-" for s in ("prior", "registration", "fused"))
        m1s = f"{np.mean(ne_1s):.2f}" if ne_1s else "-"
        blocks = f"{np.mean(ne_block['trans']):.2f} / {np.mean(ne_block['rot']):.2f}"
        print(f"| {name} | {N} | {tr} | {rot} | {nm} | {100 * inside:.0f} % | {m1s} | [{band[0]:.2f}, {band[1]:.2f}] "
              f"| {blocks} |")
        if args.check_fused_nees:
            lo, hi = args.check_fused_nees
            mean = float(np.mean(ne["fused"]))
            if not (lo <= mean <= hi):
                print(f"fusion_nees.py: {name}: fused mean NEES {mean:.2f} outside [{lo}, {hi}]", file=sys.stderr)
                ok = False
        if args.check_block_nees:
            for block, (lo, hi) in zip(("trans", "rot"), block_bands):
                mean = float(np.mean(ne_block[block]))
                if not (lo <= mean <= hi):
                    print(f"fusion_nees.py: {name}: fused {block} mean NEES {mean:.2f} outside [{lo}, {hi}]",
                          file=sys.stderr)
                    ok = False
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""The fusion bench's table (docs/covariance.md): per sequence and method, ATE [m] / RPE per second trans [mm] /
rot [deg] / RPE per frame trans [mm] / rot [deg] / map fallbacks (jump fallbacks) and the pooled mean over sequences,
from a `dorado bench` output folder (results.csv, bench_runs.csv, each map run's summary.json).

    fusion_table.py DIR [--methods odom_doppler map_doppler@refinement=ceres ...]
"""
import argparse
import csv
import json
import os
from collections import defaultdict

METRICS = [("ate", "m", 1.0, 3), ("rpe_second_translation", "m", 1000.0, 1), ("rpe_second_rotation", "deg", 1.0, 3),
           ("rpe_frame_translation", "m", 1000.0, 2), ("rpe_frame_rotation", "deg", 1.0, 3)]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("dir")
    ap.add_argument("--methods", nargs="*")
    args = ap.parse_args()
    values = defaultdict(dict)
    sequences, methods = [], []
    with open(os.path.join(args.dir, "results.csv")) as f:
        for row in csv.DictReader(f):
            s, m = row["sequence"], row["method"]
            if s not in sequences:
                sequences.append(s)
            if m not in methods:
                methods.append(m)
            key = row["metric"]
            values[(s, m)][key] = float(row["rmse"] if key.startswith("ate") else row["mean"])
    methods = args.methods or methods
    runs = {}
    with open(os.path.join(args.dir, "bench_runs.csv")) as f:
        for row in csv.DictReader(f):
            runs[(row["sequence"], row["method"])] = row["run_dir"]

    def cell(s, m):
        v = values.get((s, m), {})
        parts = []
        for name, _, scale, digits in METRICS:
            key = next((k for k in v if k.startswith(name)), None)
            parts.append(f"{scale * v[key]:.{digits}f}" if key else "-")
        summary = os.path.join(runs.get((s, m), ""), "summary.json")
        if os.path.exists(summary) and "fallbacks" in json.load(open(summary)):
            d = json.load(open(summary))
            jumps = d.get("fallback_reasons", {}).get("jump outside the prior", 0)
            parts.append(f"{d['fallbacks']} fb ({jumps} jump) / {d['scans']}")
        return " / ".join(parts)

    print("| sequence | " + " | ".join(methods) + " |")
    print("|---|" + "---|" * len(methods))
    for s in sequences:
        print(f"| {s} | " + " | ".join(cell(s, m) for m in methods) + " |")
    pooled = []
    for m in methods:
        parts = []
        for name, _, scale, digits in METRICS:
            xs = [scale * v[k] for s in sequences for v in [values.get((s, m), {})] for k in v if k.startswith(name)]
            parts.append(f"{sum(xs) / len(xs):.{digits}f}" if xs else "-")
        pooled.append(" / ".join(parts))
    print("| mean | " + " | ".join(pooled) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The fusion bench's table (docs/covariance.md): per sequence and method, ATE [m] / RPE per second trans [mm] /
rot [deg] / RPE per frame trans [mm] / rot [deg] / map fallbacks and the pooled mean over sequences,
from a `dorado bench` output folder (results.csv, bench_runs.csv, each map run's summary.json).

    fusion_table.py DIR [DIR ...] [--methods odom_doppler map_doppler@mapper.registration_weak_ratio=0.05 ...]
(several DIRs of the same sequences, e.g. runs of the same data with other grids, are merged)
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
    ap.add_argument("dirs", nargs="+")
    ap.add_argument("--methods", nargs="*")
    args = ap.parse_args()
    values = defaultdict(dict)
    sequences, methods = [], []
    runs = {}
    for d in args.dirs:
        with open(os.path.join(d, "results.csv")) as f:
            reader = csv.reader(f)
            header = next(reader)
            for cells in reader:
                # a grid variant of two keys has a comma in its name, which results.csv quotes
                # (folders written by older builds did not: their extra cells are joined back)
                extra = len(cells) - len(header)
                cells = [cells[0], ",".join(cells[1:2 + extra])] + cells[2 + extra:]
                row = dict(zip(header, cells))
                s, m = row["sequence"], row["method"]
                if s not in sequences:
                    sequences.append(s)
                if m not in methods:
                    methods.append(m)
                key = row["metric"]
                values[(s, m)][key] = float(row["rmse"] if key.startswith("ate") else row["mean"])
        with open(os.path.join(d, "bench_runs.csv")) as f:
            reader = csv.reader(f)
            header = next(reader)
            for cells in reader:
                extra = (len(cells) - len(header)) // 2  # the method's commas, repeated in run_dir
                method = ",".join(cells[1:2 + extra])
                runs[(cells[0], method)] = ",".join(cells[2 + extra:3 + 2 * extra])
    methods = args.methods or methods
    sequences = [s for s in sequences if s != "all"]  # the pooled mean is computed below

    def cell(s, m):
        v = values.get((s, m), {})
        parts = []
        for name, _, scale, digits in METRICS:
            key = next((k for k in v if k.startswith(name)), None)
            parts.append(f"{scale * v[key]:.{digits}f}" if key else "-")
        summary = os.path.join(runs.get((s, m), ""), "summary.json")
        if os.path.exists(summary) and "fallbacks" in json.load(open(summary)):
            d = json.load(open(summary))
            parts.append(f"{d['fallbacks']} fb / {d['scans']}")
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
    print("| mean of the sequences | " + " | ".join(pooled) + " |")


if __name__ == "__main__":
    main()

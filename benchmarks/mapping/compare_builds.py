#!/usr/bin/python3
"""The `doppler`-prior map of other dorado builds (older releases) on the simulated data of a finished
`dorado bench` run, scored beside that run's own trajectories, all by this build's `dorado eval` against the
exact trajectory. One table: ATE rmse [m] / RPE per second trans [mm] / rot [deg] / RPE per frame trans [mm] /
rot [deg] (means), per sequence and the mean of the sequences.

    compare_builds.py BENCH_DIR --dorado build/apps/dorado --run odom_doppler --run map_doppler \
        --build old=/path/to/old/build/apps/dorado [--build ...]

An older build may not know a key of today's dataset.yaml: each key it names as unknown is dropped from its copy
(printed), as that build never had the setting. Its runs go to BENCH_DIR/builds/LABEL/SEQ (kept, not rerun).
"""
import argparse
import json
import os
import re
import subprocess
import sys
import tempfile


def dataset_copy(bench, seq, dest):
    """The sequence's dataset.yaml with its relative files made absolute."""
    data = os.path.join(bench, "data", seq)
    with open(os.path.join(data, "dataset.yaml")) as f:
        text = f.read()
    text = re.sub(r"(path:\s*)([^\s/][^\s]*)", lambda m: m.group(1) + os.path.join(data, m.group(2)),
                  text)
    with open(dest, "w") as f:
        f.write(text)


def run_old(binary, label, bench, seq):
    out_root = os.path.join(bench, "builds", label)
    os.makedirs(out_root, exist_ok=True)
    out = os.path.join(out_root, seq)
    trajectory = os.path.join(out, "trajectory.tum")
    if os.path.exists(trajectory):
        return trajectory
    dataset = os.path.join(out_root, seq + ".dataset.yaml")
    dataset_copy(bench, seq, dataset)
    for _ in range(20):
        proc = subprocess.run([binary, "map", dataset, "--prior", "doppler", "--out", out, "--accept-implausible"],
                              stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if proc.returncode == 0 and os.path.exists(trajectory):
            return trajectory
        unknown = re.search(r"key '([^']+)': unknown key", proc.stderr)
        if not unknown:
            sys.exit(f"compare_builds: {label} on {seq} failed:\n{proc.stderr.strip()}")
        leaf = unknown.group(1).split(".")[-1]
        print(f"compare_builds: {label} does not know {unknown.group(1)}: dropped for {seq}",
              file=sys.stderr)
        with open(dataset) as f:
            lines = [line for line in f if not re.match(r"\s*" + re.escape(leaf) + r":", line)]
        with open(dataset, "w") as f:
            f.writelines(lines)
    sys.exit(f"compare_builds: {label} on {seq}: too many unknown keys")


def score(dorado, truth, trajectory):
    values = []
    for extra in ([], ["--delta", "1", "--unit", "s"]):
        fd, path = tempfile.mkstemp(suffix=".json")
        os.close(fd)
        try:
            subprocess.run([dorado, "eval", "--gt", truth, "--est", trajectory, "--json", path] + extra,
                           stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=True)
            with open(path) as f:
                values.append(json.load(f))
        finally:
            os.remove(path)
    frame, second = values
    return (frame["ate_m"]["rmse"], 1e3 * second["rpe_translation_m"]["mean"],
            second["rpe_rotation_deg"]["mean"], 1e3 * frame["rpe_translation_m"]["mean"],
            frame["rpe_rotation_deg"]["mean"])


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("bench", help="a finished `dorado bench` output folder")
    ap.add_argument("--dorado", default="build/apps/dorado", help="this build (scores every run)")
    ap.add_argument("--run", action="append", default=[], help="a run of the bench (runs/SEQ/RUN)")
    ap.add_argument("--build", action="append", default=[], help="LABEL=PATH of another dorado")
    a = ap.parse_args()
    builds = []
    for spec in a.build:
        label, _, path = spec.partition("=")
        if not path or not os.access(path, os.X_OK):
            sys.exit(f"compare_builds: --build {spec}: expected LABEL=PATH to a dorado program")
        builds.append((label, path))
    sequences = sorted(os.listdir(os.path.join(a.bench, "data")))
    columns = [label for label, _ in builds] + a.run
    print("| sequence | " + " | ".join(columns) + " |")
    print("|---" * (len(columns) + 1) + "|")
    pooled = {c: [] for c in columns}
    for seq in sequences:
        truth = os.path.join(a.bench, "data", seq, "true_trajectory.tum")
        cells = []
        for label, path in builds:
            pooled[label].append(score(a.dorado, truth, run_old(path, label, a.bench, seq)))
            cells.append(pooled[label][-1])
        for run in a.run:
            trajectory = os.path.join(a.bench, "runs", seq, run, "trajectory.tum")
            if not os.path.exists(trajectory):
                sys.exit(f"compare_builds: no {trajectory}")
            pooled[run].append(score(a.dorado, truth, trajectory))
            cells.append(pooled[run][-1])
        print(f"| {seq} | " + " | ".join("%.3f / %.1f / %.3f / %.2f / %.3f" % c for c in cells) + " |")
    means = [tuple(sum(v[i] for v in pooled[c]) / len(pooled[c]) for i in range(5)) for c in columns]
    print("| mean of the sequences | " +
          " | ".join("%.3f / %.1f / %.3f / %.2f / %.3f" % m for m in means) + " |")


if __name__ == "__main__":
    main()

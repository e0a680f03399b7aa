#!/usr/bin/python3
"""Cost of one simulated sequence through dorado: CPU seconds (user + sys) and peak RSS of
`dorado simulate`, `dorado odometry` and `dorado map`, and the mapper's time per scan (median and
p95 of the whole pipeline and of each stage, from summary.json). Prints numbers; asserts nothing.

Usage: run_cost.py BUILD_DIR [--sequence seq04] [--duration 60] [--prior doppler] [--runs 1]
                   [--seed 1] [--cpu N]
  --runs N   runs the mapper N times on the same data (the spread is the machine's);
  --cpu N    pins the mapper to core N with taskset (one core, as in docs/speed.md).
e.g. benchmarks/run_cost.py build --sequence seq04 --duration 60 --runs 3 --cpu 1
"""
import argparse
import json
import os
import shutil
import subprocess
import sys
import tempfile


def run(cmd):
    """Runs cmd, returns (CPU seconds, peak RSS in MB) of the child."""
    proc = subprocess.Popen(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(proc.pid, 0)
    err = proc.stderr.read().decode(errors="replace")
    proc.stderr.close()
    if os.waitstatus_to_exitcode(status) != 0:
        sys.exit(f"run_cost: {' '.join(cmd)} failed:\n{err}")
    return usage.ru_utime + usage.ru_stime, usage.ru_maxrss / 1024.0


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("build")
    ap.add_argument("--sequence", default="seq04")
    ap.add_argument("--duration", type=float, default=60.0)
    ap.add_argument("--prior", default="doppler")
    ap.add_argument("--runs", type=int, default=1)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--cpu", type=int, default=None)
    a = ap.parse_args()
    dorado = os.path.join(a.build, "apps", "dorado")
    if not os.access(dorado, os.X_OK):
        sys.exit(f"run_cost: no dorado program at {dorado} (build it first)")
    pin = ["taskset", "-c", str(a.cpu)] if a.cpu is not None and shutil.which("taskset") else []
    work = tempfile.mkdtemp(prefix="dorado_run_cost_")
    try:
        sim = os.path.join(work, "sim")
        cpu, rss = run([dorado, "simulate", "--sequence", a.sequence, "--duration", str(a.duration),
                        "--seed", str(a.seed), "--out", sim])
        print(f"{a.sequence}, {a.duration:g} s, seed {a.seed}")
        print(f"{'simulate':28s} CPU {cpu:7.2f} s   peak RSS {rss:7.1f} MB")
        cpu, rss = run(pin + [dorado, "odometry", sim, "--accept-implausible", "--out", os.path.join(work, "odo")])
        print(f"{'odometry':28s} CPU {cpu:7.2f} s   peak RSS {rss:7.1f} MB")
        stages = None
        for r in range(a.runs):
            out = os.path.join(work, f"map{r}")
            cpu, rss = run(pin + [dorado, "map", sim, "--prior", a.prior, "--accept-implausible", "--out", out])
            with open(os.path.join(out, "summary.json")) as f:
                summary = json.load(f)
            total = summary["time_per_scan_ms"]
            print(f"{'map --prior ' + a.prior:28s} CPU {cpu:7.2f} s   peak RSS {rss:7.1f} MB   "
                  f"per scan median {total['median']:.2f} ms, p95 {total['p95']:.2f} ms, "
                  f"local map max {summary['local_map_points_max']}, written map "
                  f"{summary['map_points']} points")
            stages = summary["time_per_stage_ms"]
            print("    stages (median / p95 ms): " + ", ".join(
                f"{name} {s['median']:.3f} / {s['p95']:.3f}" for name, s in stages.items()))
    finally:
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main()

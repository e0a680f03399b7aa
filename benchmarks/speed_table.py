#!/usr/bin/python3
"""docs/speed.md's measured tables: `dorado odometry` and `dorado map --prior doppler` per scan on
simulated drives, printed with the machine they ran on and as ratios (what a page may compare
across machines).

    benchmarks/speed_table.py --out DIR [--dorado build/apps/dorado] [--duration 30] [--runs 3]

Each sequence (seq04, seq08, car_urban; seed 4) is simulated once; odometry and map run --runs
times pinned to one core (taskset -c 1 when there is a second core), and the median of the runs'
per-scan medians and p95s is printed as one generated table (between table markers) on stdout.
"""
import argparse
import json
import os
import platform
import shutil
import statistics
import subprocess
import sys

SEQUENCES = ("seq04", "seq08", "car_urban")


def run(cmd):
    p = subprocess.run(cmd, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
    if p.returncode != 0:
        sys.exit("speed_table: %s failed:\n%s" % (" ".join(cmd), p.stderr))


def machine():
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            for line in f:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return "%s, %d cores, load average %.1f at the start" % (model, os.cpu_count() or 0, os.getloadavg()[0])


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--dorado", default="build/apps/dorado")
    ap.add_argument("--duration", type=float, default=30.0)
    ap.add_argument("--runs", type=int, default=3)
    a = ap.parse_args()
    dorado = os.path.abspath(a.dorado)
    os.makedirs(a.out, exist_ok=True)
    pin = ["taskset", "-c", "1"] if (os.cpu_count() or 1) > 1 and shutil.which("taskset") else []
    host = machine()
    rows = []
    for seq in SEQUENCES:
        sim = os.path.join(a.out, seq)
        if not os.path.exists(os.path.join(sim, "dataset.yaml")):
            run([dorado, "simulate", "--sequence", seq, "--duration", "%g" % a.duration, "--seed", "4", "--out", sim])
        odo_med, map_med, map_p95, stages = [], [], [], []
        for r in range(a.runs):
            odo = os.path.join(a.out, "%s_odo%d" % (seq, r))
            run(pin + [dorado, "odometry", sim, "--accept-implausible", "--out", odo])
            with open(os.path.join(odo, "summary.json")) as f:
                odo_med.append(json.load(f)["time_per_scan_ms"]["median"])
            out = os.path.join(a.out, "%s_map%d" % (seq, r))
            run(pin + [dorado, "map", sim, "--prior", "doppler", "--accept-implausible", "--out", out])
            with open(os.path.join(out, "summary.json")) as f:
                s = json.load(f)
            map_med.append(s["time_per_scan_ms"]["median"])
            map_p95.append(s["time_per_scan_ms"]["p95"])
            stages.append(sum(v["median"] for v in s["time_per_stage_ms"].values()))
        m, p, o = statistics.median(map_med), statistics.median(map_p95), statistics.median(odo_med)
        rows.append("| %s | %.2f | %.2f | %.2f | %.2f | %.3f | %.0f |" % (
            seq, m, p, p / m, statistics.median(stages), o, m / o))
    print("<!-- table speed_per_scan -->")
    print("| sequence (%g s, seed 4) | map median [ms] | map p95 [ms] | p95 / median | mapper stages, sum of medians [ms] "
          "| odometry median [ms] | map / odometry |" % a.duration)
    print("|---|---:|---:|---:|---:|---:|---:|")
    for row in rows:
        print(row)
    print("<!-- end table -->")
    print()
    print("<!-- table speed_machine -->")
    print("| machine | pinned | runs |")
    print("|---|---|---:|")
    print("| %s | %s | %d (the median of their medians) |" % (host, "taskset -c 1" if pin else "no", a.runs))
    print("<!-- end table -->")


if __name__ == "__main__":
    main()

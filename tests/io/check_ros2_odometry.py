#!/usr/bin/python3
"""`dorado odometry` gives the same trajectory from the ROS1 bag of a simulated sequence and from its
rosbag2 copies (.db3, zstd .mcap, lz4 .mcap, a split folder) written by rosbag2_writer.py.

  check_ros2_odometry.py DORADO OUT_DIR
Prints the largest difference per recording; fails when one exceeds 1e-9 (TUM values, 9 decimals).
"""
import math
import os
import subprocess
import sys

HERE = os.path.dirname(os.path.abspath(__file__))


def rows(path):
    """The data rows of a TUM file or a CSV with a header: numbers as floats, text as it is."""
    out = []
    with open(path) as f:
        lines = [line for line in f if line.strip() and not line.startswith("#")]
    skip = -1
    if path.endswith(".csv"):  # every column but the measured time per scan
        skip = lines[0].strip().split(",").index("time_ms")
        lines = lines[1:]
    for line in lines:
        fields = line.strip().split("," if path.endswith(".csv") else None)
        if skip >= 0:
            del fields[skip]
        row = []
        for v in fields:
            try:
                row.append(float(v))
            except ValueError:
                row.append(v)
        out.append(row)
    return out


def difference(a, b):
    if isinstance(a, str) or isinstance(b, str):
        return 0.0 if a == b else math.inf
    if math.isnan(a) or math.isnan(b):
        return 0.0 if math.isnan(a) and math.isnan(b) else math.inf
    return abs(a - b)


def run(*args):
    subprocess.run(args, check=True, stdout=subprocess.DEVNULL)


def main(dorado, out):
    sim = os.path.join(out, "sim")
    run(dorado, "simulate", "--sequence", "seq04", "--duration", "10", "--out", sim)
    run(sys.executable, os.path.join(HERE, "make_ros2_bags.py"), "convert",
        os.path.join(sim, "data.bag"), os.path.join(out, "ros2"))
    template = open(os.path.join(sim, "dataset.yaml")).read()
    recordings = {"ros1": os.path.join(sim, "data.bag")}
    for name in ("data.db3", "data.mcap", "data_lz4.mcap", "data_split"):
        recordings[name] = os.path.join(out, "ros2", name)
    results = {}
    for name, path in recordings.items():
        description = os.path.join(out, name + ".yaml")
        with open(description, "w") as f:
            f.write(template.replace("path: data.bag", "path: " + path)
                    .replace("path: ground_truth.tum", "path: " + os.path.join(sim, "ground_truth.tum")))
        run(dorado, "odometry", description, "--accept-implausible", "--out", os.path.join(out, "odo_" + name))
        results[name] = {f: rows(os.path.join(out, "odo_" + name, f))
                         for f in ("trajectory.tum", "velocities.csv")}
    worst = 0.0
    reference = results["ros1"]
    for name, result in results.items():
        if name == "ros1":
            continue
        diff = 0.0
        for f, table in result.items():
            if len(table) != len(reference[f]) or len(table) < 100:
                sys.exit("%s: %s has %d rows, the ROS1 result %d" % (name, f, len(table), len(reference[f])))
            diff = max([diff] + [difference(a, b) for r, s in zip(table, reference[f]) for a, b in zip(r, s)])
        print("%-14s %d poses, max |difference| to ROS1 = %.3g" % (name, len(result["trajectory.tum"]), diff))
        worst = max(worst, diff)
    if worst > 1e-9:
        sys.exit("trajectories differ by %.3g > 1e-9" % worst)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])

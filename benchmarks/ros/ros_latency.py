#!/usr/bin/python3
"""dorado_ros latency from a message's arrival (the subscriber callback) to the publish of its
/doppler_odom, median and p95, on a real rosmaster with `rosbag play` of a simulated bag, with the
mapper off and on. Prints numbers; asserts nothing.
Usage: ros_latency.py BUILD_DIR [RATE]   (e.g. benchmarks/ros/ros_latency.py build 1)"""
import json
import os
import shutil
import subprocess
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests",
                                "ros"))
import ros_harness as h  # noqa: E402


def main(build, rate):
    why = h.ros_missing()
    if why:
        print(f"skipped: {why}")
        return
    dorado = os.path.join(build, "apps", "dorado")
    dorado_ros = os.path.join(build, "ros", "package", "dorado_ros", "dorado_ros")
    work = h.work_dir("dorado_ros_latency_")
    graph = None
    try:
        sim = os.path.join(work, "sim")
        subprocess.run([dorado, "simulate", "--sequence", "seq04", "--duration", "10", "--out",
                        sim], check=True, stderr=subprocess.DEVNULL)
        graph = h.Graph(work)
        recorder = h.Recorder(["/doppler_odom"])
        for mapper in ("false", "true"):
            name = f"mapper_{mapper}"
            params = {"config": os.path.join(sim, "dataset.yaml"), "mapper": mapper,
                      "summary_file": os.path.join(work, name + ".json")}
            h.run_node_on_bag(graph, recorder, dorado_ros, params,
                              os.path.join(sim, "data.bag"), rate, name)
            with open(params["summary_file"]) as f:
                s = json.load(f)
            lat = s["latency_ms"]
            print(f"dorado_ros seq04 10 s at {rate}x, mapper {mapper}: {s['published']} of "
                  f"{s['received']} scans published, dropped {s['dropped'] or 'none'}; latency "
                  f"arrival->publish median {lat['median']:.2f} ms, p95 {lat['p95']:.2f} ms")
    finally:
        if graph:
            graph.close()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 1.0)

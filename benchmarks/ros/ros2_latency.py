#!/usr/bin/python3
"""dorado_ros2 latency from a scan's arrival (the DDS reader's callback) to the write of its
/dorado/map_odom (mapper on; /doppler_odom with it off), median and p95, over DDS on localhost
with `dorado replay` of a simulated recording at RATE: the mapper off, on (loop closure on, the
default), and on with loop closure off (its thread must not delay a scan). Prints numbers; asserts
nothing.
Usage: ros2_latency.py BUILD_DIR [RATE] [SECONDS]   (e.g. benchmarks/ros/ros2_latency.py build 1)"""
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "tests",
                                "ros2"))
import dds_harness as h  # noqa: E402


def main(build, rate, seconds):
    why = h.missing()
    if why:
        print(f"skipped: {why}")
        return
    tools = [os.path.join(build, "apps", "dorado"), os.path.join(build, "ros2", "dorado_ros2"),
             os.path.join(build, "tests", "ros2", "dds_recorder")]
    work = tempfile.mkdtemp(prefix="dorado_ros2_latency_")
    dds = h.Dds(work, *tools)
    try:
        recording = h.Recording(tools[0], work, seconds)
        no_loops = os.path.join(work, "no_loops.yaml")
        with open(no_loops, "w") as f:
            f.write("loop_closure:\n  enabled: false\n")
        for mapper, loops in ((False, False), (True, True), (True, False)):
            extra = {} if loops or not mapper else {"mapper_config": no_loops}
            run = dds.run_node(f"mapper_{mapper}_{loops}", 69, recording.path, rate,
                               expect=recording.scans, config=recording.dataset, mapper=mapper,
                               **extra)
            s, lat = run.summary, run.summary["latency_ms"]
            what = ("on, loop closure " + ("on" if loops else "off")) if mapper else "off"
            print(f"dorado_ros2 seq04 {seconds} s at {rate}x, mapper {what}: "
                  f"{s['published']} of {s['received']} scans published, dropped "
                  f"{s['dropped'] or 'none'}; latency scan arrival -> "
                  f"{'/dorado/map_odom' if mapper else '/doppler_odom'} median {lat['median']:.2f} "
                  f"ms, p95 {lat['p95']:.2f} ms; the front end's own time median "
                  f"{s['front_end_ms']['median']:.2f} ms; the node's CPU time per scan median "
                  f"{s['worker_cpu_ms']['median']:.2f} ms, p95 {s['worker_cpu_ms']['p95']:.2f} ms "
                  f"(load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores)")
    finally:
        dds.close()
        shutil.rmtree(work, ignore_errors=True)


if __name__ == "__main__":
    main(sys.argv[1], float(sys.argv[2]) if len(sys.argv) > 2 else 1.0,
         int(sys.argv[3]) if len(sys.argv) > 3 else 10)

#!/usr/bin/python3
"""dorado_ros against the real thing: a rosmaster on a free port, the node, `rosbag play`
of a simulated bag at 1x and 5x, a bag with out-of-order and duplicate stamps, and a wrong field
map. Skipped (exit 77) where ROS1 is absent.
Usage: test_dorado_ros.py DORADO DORADO_ROS"""
import json
import math
import os
import shutil
import subprocess
import sys
import unittest

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import ros_harness as h  # noqa: E402

DORADO, DORADO_ROS = sys.argv[1], sys.argv[2]
RADAR = "/hugin_raf_1/radar_data"


def quat_difference(a, b):
    """Largest component difference of two unit quaternions, up to their sign (the TUM file has
    9 decimals: an angle through acos would read its rounding as 5e-5 rad)."""
    sign = 1.0 if sum(x * y for x, y in zip(a, b)) >= 0 else -1.0
    return max(abs(x - sign * y) for x, y in zip(a, b))


def max_difference(published, reference):
    """Largest position difference [m] and quaternion component difference of published poses against
    the reference poses with the same stamps; the stamps missing from the reference."""
    dp = dq = 0.0
    missing = 0
    for stamp, pose, _, _ in published:
        ref = reference.get(stamp)
        if ref is None:
            missing += 1
            continue
        dp = max(dp, max(abs(a - b) for a, b in zip(pose[:3], ref[:3])))
        dq = max(dq, quat_difference(pose[3:], ref[3:]))
    return dp, dq, missing


def rewrite_bag(src, dst, duplicates, older, seconds):
    """The radar scans of the first `seconds` of src, with a copy of each scan in `duplicates`
    (same stamp) and, after each scan in `older`, a scan stamped 50 ms before it (bag time keeps
    increasing: `rosbag play` sends them in this order)."""
    import rosbag
    import rospy
    with rosbag.Bag(src) as bag_in, rosbag.Bag(dst, "w") as bag_out:
        start = None
        index = 0
        for topic, msg, t in bag_in.read_messages(topics=[RADAR]):
            start = start or t
            if (t - start).to_sec() > seconds:
                break
            bag_out.write(topic, msg, t)
            if index in duplicates:
                bag_out.write(topic, msg, t + rospy.Duration(0, 1000))
            if index in older:
                msg.header.stamp -= rospy.Duration(0, 50_000_000)
                bag_out.write(topic, msg, t + rospy.Duration(0, 2000))
            index += 1
    return index


def cut_bag(src, dst, seconds, drop_scans=(), imu_until=None, imu_topic="/imu/data"):
    """The first `seconds` of src: radar scans except those in the `drop_scans` (start, end)
    windows [s], and the IMU until `imu_until` [s] (none when None). Returns the scans kept."""
    import rosbag
    topics = [RADAR] + ([imu_topic] if imu_until is not None else [])
    kept = 0
    with rosbag.Bag(src) as bag_in, rosbag.Bag(dst, "w") as bag_out:
        start = None
        for topic, msg, t in bag_in.read_messages(topics=topics):
            start = start or t
            age = (t - start).to_sec()
            if age > seconds:
                break
            if topic == RADAR:
                if any(a < age < b for a, b in drop_scans):
                    continue
                kept += 1
            elif age > imu_until:
                continue
            bag_out.write(topic, msg, t)
    return kept


class DoradoRos(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = h.work_dir("dorado_ros_test_")
        cls.sim = os.path.join(cls.dir, "sim")
        subprocess.run([DORADO, "simulate", "--sequence", "seq04", "--duration", "10", "--out",
                        cls.sim], check=True, stderr=subprocess.DEVNULL)
        cls.dataset = os.path.join(cls.sim, "dataset.yaml")
        cls.bag = os.path.join(cls.sim, "data.bag")
        subprocess.run([DORADO, "odometry", cls.dataset, "--accept-implausible", "--out", os.path.join(cls.dir, "odom")],
                       check=True, stderr=subprocess.DEVNULL)
        subprocess.run([DORADO, "map", cls.dataset, "--accept-implausible", "--out", os.path.join(cls.dir, "map")],
                       check=True, stderr=subprocess.DEVNULL)
        cls.odom = h.read_tum(os.path.join(cls.dir, "odom", "trajectory.tum"))
        cls.map = h.read_tum(os.path.join(cls.dir, "map", "trajectory.tum"))
        cls.graph = h.Graph(cls.dir)
        cls.recorder = h.Recorder(["/doppler_odom", "/dorado/map_odom", "/dorado/smoothed_odom"])

    @classmethod
    def tearDownClass(cls):
        cls.graph.close()
        if os.environ.get("DORADO_KEEP_TEST_DIR") is None:
            shutil.rmtree(cls.dir, ignore_errors=True)

    def params(self, name, **extra):
        p = {"config": self.dataset, "tf_from_frame": "odom", "tf_to_frame": "base_link",
             "summary_file": os.path.join(self.dir, name + ".json")}
        p.update(extra)
        return p

    def run_node(self, name, bag, rate, topics=("/doppler_odom",), expect=None, **extra):
        params = self.params(name, **extra)
        code, err = h.run_node_on_bag(self.graph, self.recorder, DORADO_ROS, params, bag, rate,
                                      name, topics, expect)
        self.assertEqual(code, 0, f"{name}: dorado_ros exit {code}\n{err}")  # SIGINT: clean exit
        with open(params["summary_file"]) as f:
            return json.load(f), err

    def test_1x_equals_the_command_line_and_5x_drops_are_counted(self):
        # queue_size 1000: no scan dropped however slow the machine (the node catches up after
        # the bag ends); the default queue is tested at 5x.
        summary, err = self.run_node("x1", self.bag, 1, ("/dorado/map_odom", "/doppler_odom"),
                                     expect=len(self.map), mapper="true", queue_size=1000)
        odom = self.recorder.messages["/doppler_odom"]
        mapped = self.recorder.messages["/dorado/map_odom"]
        print(f"1x: {len(self.odom)} scans in the bag, {len(odom)} /doppler_odom, {len(mapped)} "
              f"/dorado/map_odom; latency median {summary['latency_ms']['median']:.2f} ms, p95 "
              f"{summary['latency_ms']['p95']:.2f} ms")
        self.assertEqual(len(odom), len(self.odom), err)
        self.assertEqual(len(mapped), len(self.map), err)
        self.assertEqual(summary["dropped"], {}, err)
        # With the mapper on, the node's Doppler odometry takes the map's online yaw lever
        # (odometry.online_calibration, docs/design/attitude.md section 5) from the first update on,
        # which `dorado odometry` (no map) cannot have: compare it over the calibration's warmup.
        first = min(stamp for stamp, _, _, _ in odom)
        warmup_ns = 5_000_000_000
        odom_warmup = [m for m in odom if m[0] - first < warmup_ns]
        # The map's written poses are the smoothed ones (/dorado/smoothed_odom, about the smoother's
        # lag behind; the bag's last second stays in the window); /dorado/map_odom is the newest.
        smoothed = self.recorder.messages["/dorado/smoothed_odom"]
        self.assertGreater(len(smoothed), len(self.map) // 2)
        for published, reference, what in ((odom_warmup, self.odom, "odometry"),
                                           (smoothed, self.map, "map")):
            dp, dq, missing = max_difference(published, reference)
            print(f"1x vs dorado {what}: max |dp| {dp:.2e} m, max |dq| {dq:.2e}")
            self.assertEqual(missing, 0)
            self.assertLess(dp, 1e-6, what)
            self.assertLess(dq, 1e-6, what)
        # The covariances are filled in: the pose's grows, the twist's is positive.
        self.assertGreater(odom[-1][2][0], odom[1][2][0])
        self.assertGreater(min(odom[-1][3][i * 7] for i in range(6)), 0.0)
        # REP 105: map -> odom -> base_link, composed by tf2 from /tf, is /dorado/map_odom's pose;
        # its pose covariance is the mapper's (positive definite after the first scan).
        composed = [(stamp, self.recorder.lookup("map", "base_link", stamp), (), ())
                    for stamp, _, _, _ in mapped]
        dp, dq, missing = max_difference(composed, {m[0]: m[1] for m in mapped})
        print(f"1x: tf2 map -> base_link vs /dorado/map_odom: max |dp| {dp:.2e} m, |dq| {dq:.2e}")
        self.assertEqual(missing, 0)
        self.assertLess(dp, 1e-6)
        self.assertLess(dq, 1e-6)
        for _, _, pose_cov, _ in mapped[1:]:
            eig = np.linalg.eigvalsh(np.array(pose_cov).reshape(6, 6))
            self.assertGreater(eig.min(), 0.0)

        summary, err = self.run_node("x5", self.bag, 5, ("/dorado/map_odom", "/doppler_odom"),
                                     mapper="true")
        mapped = self.recorder.messages["/dorado/map_odom"]
        dropped = sum(summary["dropped"].values())
        print(f"5x: {summary['received']} received, {summary['published']} published, dropped "
              f"{summary['dropped']}; latency median {summary['latency_ms']['median']:.2f} ms, "
              f"p95 {summary['latency_ms']['p95']:.2f} ms")
        self.assertEqual(summary["received"], len(self.odom))
        self.assertEqual(summary["published"] + dropped, summary["received"])
        self.assertEqual(len(mapped), summary["published"])
        self.assertIn("dropped: " + ("none" if dropped == 0 else "late"), err)
        if dropped:
            self.assertIn("late (processing behind): dropped a scan", err)
        # Sane: finite, no reset (the gaps the drops make are integrated over, not a stall), and
        # near the 1x map: within 0.5 m + 20 % of the path so far (a scan's twist integrated over
        # the dropped scans' intervals drifts; on a quiet machine nothing is dropped).
        self.assertEqual(summary["resets"], 0)
        stamps = sorted(self.map)
        path, travelled = 0.0, {stamps[0]: 0.0}
        for a, b in zip(stamps, stamps[1:]):
            path += math.dist(self.map[a][:3], self.map[b][:3])
            travelled[b] = path
        worst = max(math.dist(pose[:3], self.map[stamp][:3]) - 0.2 * travelled[stamp]
                    for stamp, pose, _, _ in mapped)
        print(f"5x: worst distance to the 1x map trajectory beyond 20 % of the path {worst:.3f} m")
        self.assertTrue(all(math.isfinite(v) for m in mapped for v in m[1]))
        self.assertLess(worst, 0.5)

    def test_out_of_order_and_duplicate_stamps_are_dropped_and_reported(self):
        bag = os.path.join(self.dir, "faults.bag")
        scans = rewrite_bag(self.bag, bag, duplicates={5, 9}, older={12, 20, 21}, seconds=3)
        summary, err = self.run_node("faults", bag, 2, expect=scans, queue_size=1000)
        print(f"faults: {scans} scans + 2 duplicates + 3 older; dropped {summary['dropped']}")
        self.assertEqual(summary["dropped"], {"duplicate stamp": 2, "out of order": 3})
        self.assertEqual(summary["published"], scans)
        self.assertEqual(len(self.recorder.messages["/doppler_odom"]), scans)
        self.assertEqual(err.count("duplicate stamp: dropped a scan"), 1, err)  # once, summarised
        self.assertEqual(err.count("out of order: dropped a scan"), 1, err)
        self.assertIn("duplicate stamp 2", err)
        dp, dq, missing = max_difference(self.recorder.messages["/doppler_odom"], self.odom)
        self.assertEqual(missing, 0)
        self.assertLess(dp, 1e-6)

    def test_gaps_are_integrated_over_or_reset(self):
        bag = os.path.join(self.dir, "gaps.bag")
        # 0.57 s without a scan (> 5 intervals of 67 ms: integrated), then 1.27 s (> max_gap_s 1).
        scans = cut_bag(self.bag, bag, 4, drop_scans=[(1.0, 1.5), (2.0, 3.2)])
        summary, err = self.run_node("gaps", bag, 2, expect=scans, queue_size=1000)
        print(f"gaps: {scans} scans, resets {summary['resets']}, warnings {summary['warnings']}")
        self.assertEqual(summary["published"], scans)
        self.assertEqual(summary["resets"], 1)
        self.assertEqual(summary["warnings"].get("gap integrated over"), 1)
        self.assertEqual(err.count("starting over at the last pose"), 1, err)
        odom = self.recorder.messages["/doppler_odom"]
        # Before the first gap the poses are the command line's; across it one scan's twist is
        # integrated over 0.57 s instead of eight scans' (sane, not equal) until the reset.
        start = min(self.odom)
        dp, _, _ = max_difference([m for m in odom if m[0] < start + 1.0e9], self.odom)
        self.assertLess(dp, 1e-6)
        dp, _, _ = max_difference([m for m in odom if m[0] < start + 2.0e9], self.odom)
        print(f"gaps: largest distance to the command line's poses before the reset {dp:.3f} m")
        self.assertLess(dp, 0.2)
        self.assertTrue(all(math.isfinite(v) for m in odom for v in m[1]))

    def test_an_imu_stall_falls_back_to_doppler_once(self):
        bag = os.path.join(self.dir, "imu_stall.bag")
        scans = cut_bag(self.bag, bag, 3, imu_until=1.5)
        summary, err = self.run_node("imu_stall", bag, 1, ("/dorado/map_odom", "/doppler_odom"),
                                     expect=scans, mapper="true", prior="imu", queue_size=1000)
        print(f"imu stall: {scans} scans, warnings {summary['warnings']}")
        self.assertEqual(summary["published"], scans)
        self.assertEqual(summary["warnings"].get("imu stalled"), 1)
        self.assertEqual(err.count("has stalled"), 1, err)
        self.assertIn("the doppler prior stands in", err)
        mapped = self.recorder.messages["/dorado/map_odom"]
        worst = max(math.dist(pose[:3], self.map[stamp][:3]) for stamp, pose, _, _ in mapped)
        self.assertLess(worst, 0.5)

    def test_a_missing_field_is_one_clear_error(self):
        wrong = h.misspelled_doppler_field(self.dataset, os.path.join(self.dir, "wrong_field.yaml"))
        bag = os.path.join(self.dir, "short.bag")
        scans = rewrite_bag(self.bag, bag, duplicates=set(), older=set(), seconds=2)
        summary, err = self.run_node("missing_field", bag, 2, config=wrong)
        self.assertEqual(err.count("its fields:"), 1, err)  # one error, not one per scan
        self.assertIn("dopler", err)
        self.assertEqual(summary["published"], 0)
        self.assertEqual(sum(summary["dropped"].values()), scans)


if __name__ == "__main__":
    why = h.ros_missing()
    if why:
        print(f"dorado_ros tests skipped: {why}")
        sys.exit(h.SKIP)
    unittest.main(argv=sys.argv[:1], verbosity=2, warnings="ignore")

#!/usr/bin/python3
"""dorado_ros2 over DDS on localhost, without ROS 2 (dds_harness.py): `dorado replay` publishes a
rosbag2 copy of a simulated recording, the node processes it, and dds_recorder (a DDS subscriber
decoding with the rosbag2 reader's codec) records /doppler_odom, /dorado/map_odom,
/dorado/smoothed_odom and the publications it discovers. Checked: the smoothed trajectory equals
`dorado map`'s at 1x, drops at 5x are counted, ROS 2's topic, type and QoS conventions, the faults
(out of order, duplicate, undecodable, a stalled IMU, a publisher that vanishes and comes back)
and ROS_DOMAIN_ID. Each test has its own domains (61..68). Skipped (exit 77) where python3-rosbag
is absent (the recording is converted from the simulator's ROS1 bag).
Usage: test_dorado_ros2.py DORADO DORADO_ROS2 DDS_RECORDER"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import unittest

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import dds_harness as h  # noqa: E402
from dds_harness import IMU, RADAR  # noqa: E402

DORADO, NODE, RECORDER = sys.argv[1:4]


class DoradoRos2(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="dorado_ros2_test_")
        rec = h.Recording(DORADO, cls.dir, 6)
        cls.messages, cls.recording, cls.scans = rec.messages, rec.path, rec.scans
        cls.dataset, cls.map = rec.dataset, rec.map

    @classmethod
    def tearDownClass(cls):
        if os.environ.get("DORADO_KEEP_TEST_DIR") is None:
            shutil.rmtree(cls.dir, ignore_errors=True)

    def setUp(self):
        self.dds = h.Dds(self.dir, DORADO, NODE, RECORDER)

    def tearDown(self):
        self.dds.close()

    def run_node(self, name, domain, recording, rate, **kwargs):
        kwargs.setdefault("config", self.dataset)
        return self.dds.run_node(name, domain, recording, rate, **kwargs)

    def max_difference(self, published, reference):
        """Largest position difference [m] over the stamps of `reference`, and the stamps missing."""
        worst, missing = 0.0, 0
        for stamp, ref in reference.items():
            pose = published.get(stamp)
            if pose is None:
                missing += 1
                continue
            worst = max(worst, max(abs(a - b) for a, b in zip(pose[:3], ref[:3])))
        return worst, missing

    # --- tests ---------------------------------------------------------------------------------
    def test_1x_equals_dorado_map_and_5x_drops_are_counted(self):
        run = self.run_node("x1", 61, self.recording, 1, expect=self.scans, mapper=True,
                            queue_size=1000)
        self.assertEqual(run.code, 0, run.err)
        latency = run.summary["latency_ms"]
        print(f"1x: {self.scans} scans in the recording; {run.summary['received']} received, "
              f"{run.count('/doppler_odom')} /doppler_odom, {run.count('/dorado/map_odom')} "
              f"/dorado/map_odom, {run.count('/dorado/smoothed_odom')} /dorado/smoothed_odom; "
              f"scan arrival -> /dorado/map_odom latency median {latency['median']:.2f} ms, "
              f"p95 {latency['p95']:.2f} ms (mapper on)")
        self.assertEqual(run.summary["received"], self.scans, run.err)
        self.assertEqual(run.summary["dropped"], {}, run.err)
        self.assertEqual(run.count("/dorado/map_odom"), self.scans)
        smoothed = run.poses("/dorado/smoothed_odom")
        self.assertEqual(len(smoothed), len(self.map))
        worst, missing = self.max_difference(smoothed, self.map)
        print(f"1x: /dorado/smoothed_odom vs dorado map's trajectory.tum: {len(self.map)} scans, "
              f"max |dp| {worst:.2e} m, missing {missing}")
        self.assertEqual(missing, 0)
        self.assertLess(worst, 1e-6)
        self.check_conventions(run.publications)

        run = self.run_node("x5", 61, self.recording, 5, mapper=True)
        self.assertEqual(run.code, 0, run.err)
        dropped = sum(run.summary["dropped"].values())
        print(f"5x: {run.summary['received']} received, {run.summary['published']} published, "
              f"dropped {run.summary['dropped']}; latency median "
              f"{run.summary['latency_ms']['median']:.2f} ms")
        self.assertEqual(run.summary["received"], self.scans)
        self.assertEqual(run.summary["published"] + dropped, run.summary["received"])
        self.assertEqual(run.count("/dorado/map_odom"), run.summary["published"])
        self.assertIn("dropped: " + ("none" if dropped == 0 else "late"), run.err)
        if dropped:
            self.assertEqual(run.err.count("late (processing behind): dropped a scan"), 1, run.err)
        self.assertEqual(run.summary["resets"], 0)
        self.assertTrue(all(math.isfinite(v) for _, _, pose in run.odometry for v in pose))

    def check_conventions(self, publications):
        """The node's and replay's publications as a ROS 2 subscriber discovers them."""
        found = {p[0]: p[1:] for p in publications}
        odometry = ["nav_msgs::msg::dds_::Odometry_", "reliable", "volatile", "keep_last", "10"]
        expected = {
            "rt/doppler_odom": odometry,
            "rt/dorado/map_odom": odometry,
            "rt/dorado/smoothed_odom": odometry,
            "rt/tf": ["tf2_msgs::msg::dds_::TFMessage_", "reliable", "volatile", "keep_last", "100"],
            "rt/tf_static": ["tf2_msgs::msg::dds_::TFMessage_", "reliable", "transient_local",
                             "keep_last", "1"],
            "rt/dorado/static_points": ["sensor_msgs::msg::dds_::PointCloud2_", "best_effort",
                                        "volatile", "keep_last", "5"],
            "rt/dorado/local_map": ["sensor_msgs::msg::dds_::PointCloud2_", "reliable",
                                    "transient_local", "keep_last", "1"],
            "rt" + RADAR: ["sensor_msgs::msg::dds_::PointCloud2_", "reliable", "volatile",
                           "keep_last", "1000"],  # dorado replay
        }
        for topic, qos in expected.items():
            self.assertEqual(found.get(topic), qos, f"{topic}: {found}")

    def test_out_of_order_and_duplicate_stamps_are_dropped_once_each(self):
        radar = [m for m in self.messages if m[0] == RADAR][:30]
        messages = []
        for i, (topic, type_name, t, data) in enumerate(radar):
            messages.append((topic, type_name, t, data))
            if i in (5, 9):  # a copy: the same stamp
                messages.append((topic, type_name, t + 1000, data))
            if i in (12, 20, 21):  # 50 ms before the scan just sent
                messages.append((topic, type_name, t + 2000,
                                 h.with_stamp(data, h.stamp_of(data) - 50_000_000)))
        path = os.path.join(self.dir, "faults.db3")
        h.write_db3(path, messages)
        run = self.run_node("faults", 63, path, 2, expect=len(radar), queue_size=1000)
        print(f"faults: {len(radar)} scans + 2 duplicates + 3 older; dropped {run.summary['dropped']}")
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(run.summary["dropped"], {"duplicate stamp": 2, "out of order": 3})
        self.assertEqual(run.summary["published"], len(radar))
        self.assertEqual(run.err.count("duplicate stamp: dropped a scan"), 1, run.err)
        self.assertEqual(run.err.count("out of order: dropped a scan"), 1, run.err)

    def test_an_undecodable_cloud_is_one_clear_error(self):
        import ros_harness
        wrong = ros_harness.misspelled_doppler_field(self.dataset,
                                                     os.path.join(self.dir, "wrong_field.yaml"))
        path = os.path.join(self.dir, "short.db3")
        radar = [m for m in self.messages if m[0] == RADAR][:20]
        h.write_db3(path, radar)
        run = self.run_node("undecodable", 64, path, 4, config=wrong)
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(run.err.count("its fields:"), 1, run.err)
        self.assertIn("dopler", run.err)
        self.assertEqual(run.summary["published"], 0)
        self.assertEqual(sum(run.summary["dropped"].values()), len(radar))

    def test_an_imu_stall_falls_back_to_doppler_once(self):
        start = self.messages[0][2]
        kept = [m for m in self.messages if m[2] - start < 3e9 and (m[0] == RADAR or m[2] - start < 1.5e9)]
        scans = sum(1 for m in kept if m[0] == RADAR)
        path = os.path.join(self.dir, "imu_stall.db3")
        h.write_db3(path, kept)
        run = self.run_node("imu_stall", 65, path, 1, topics=(RADAR, IMU), expect=scans,
                            mapper=True, prior="imu", queue_size=1000)
        print(f"imu stall: {scans} scans, warnings {run.summary['warnings']}")
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(run.summary["published"], scans)
        self.assertEqual(run.summary["warnings"].get("imu stalled"), 1)
        self.assertEqual(run.err.count("has stalled"), 1, run.err)
        self.assertIn("the doppler prior stands in", run.err)

    def test_a_publisher_that_vanishes_and_returns(self):
        # Two replays: the first 1.5 s, its publisher gone, then from 2.0 s on (0.5 s of stamps
        # between them: integrated over, no reset).
        run = self.run_node("vanish", 66, self.recording, 2,
                            replays=(("--playback-duration", "1.5"), ("--start-offset", "2.0")),
                            queue_size=1000)
        print(f"publisher vanishing: warnings {run.summary['warnings']}, published "
              f"{run.summary['published']}")
        self.assertEqual(run.code, 0, run.err)
        self.assertGreaterEqual(run.summary["warnings"].get("publisher lost", 0), 1)
        self.assertEqual(run.summary["warnings"].get("publisher back"), 1)
        self.assertEqual(run.err.count("its last publisher went away"), 1, run.err)
        self.assertEqual(run.err.count("a publisher is back"), 1, run.err)
        self.assertEqual(run.summary["dropped"], {})
        self.assertEqual(run.summary["published"], run.summary["received"])
        self.assertGreater(run.summary["published"], self.scans // 2)

    def test_use_sim_time_stamps_unstamped_scans_from_clock(self):
        # Scans stamped 0 by their driver: the node's clock (ROS time, /clock from replay --clock
        # at each message's log time) stands in.
        start = self.messages[0][2]
        zero = [(t, type_name, log, h.with_stamp(data, 0) if t == RADAR else data)
                for t, type_name, log, data in self.messages if log - start < 2e9]
        log_times = {log for t, _, log, _ in zero if t == RADAR}
        path = os.path.join(self.dir, "unstamped.db3")
        h.write_db3(path, zero)
        run = self.run_node("sim_time", 62, path, 2, replays=(("--clock",),),
                            expect=len(log_times), ros_args=("-p", "use_sim_time:=true"),
                            queue_size=1000)
        self.assertEqual(run.code, 0, run.err)
        self.assertIn("; use_sim_time", run.err)
        stamps = {stamp for t, stamp, _ in run.odometry if t == "/doppler_odom"}
        print(f"use_sim_time: {len(stamps)} scans stamped from /clock, "
              f"{len(stamps & log_times)} at their recorded log time")
        self.assertEqual(stamps, log_times)

    def test_ros_domain_id_is_honoured_and_topics_remapped(self):
        other = self.dds.start_node("other_domain", 68, config=self.dataset)
        # The radar under another name, on both sides (replay --remap, the node's -r).
        remap = RADAR + ":=/radar/points"
        run = self.run_node("domain", 67, self.recording, 5, replays=(("--remap", remap),),
                            ros_args=("-r", remap), queue_size=1000)
        self.assertIn("radar /radar/points", run.err)
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(self.dds.stop(other), 0)
        with open(other.summary_path) as f:
            other_summary = json.load(f)
        print(f"domains: node on 67 received {run.summary['received']}, node on 68 "
              f"{other_summary['received']}")
        self.assertEqual(run.summary["received"], self.scans)
        self.assertEqual(other_summary["received"], 0)
        bad = subprocess.run([NODE], env=dict(self.dds.env(0), ROS_DOMAIN_ID="abc"),
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(bad.returncode, 1)
        self.assertIn("ROS_DOMAIN_ID='abc'", bad.stderr)


if __name__ == "__main__":
    why = h.missing()
    if why:
        print(f"dorado_ros2 tests skipped: {why}")
        sys.exit(h.SKIP)
    unittest.main(argv=sys.argv[:1], verbosity=2, warnings="ignore")

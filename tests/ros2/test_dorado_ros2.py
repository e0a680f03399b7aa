#!/usr/bin/python3
"""dorado_ros2 over DDS on localhost, without ROS 2: `dorado replay` publishes a rosbag2 copy of a
simulated recording, the node processes it, and dds_recorder (a DDS subscriber decoding with the
rosbag2 reader's codec) records /doppler_odom, /dorado/map_odom, /dorado/smoothed_odom and the
publications it discovers. Checked: the smoothed trajectory equals `dorado map`'s at 1x, drops at
5x are counted, ROS 2's topic, type and QoS conventions, the faults (out of order, duplicate,
undecodable, a stalled IMU, a publisher that vanishes and comes back) and ROS_DOMAIN_ID. Each test
has its own domain (61..69). Skipped (exit 77) where ROS1's python3-rosbag is absent (the
recording is converted from the simulator's ROS1 bag).
Usage: test_dorado_ros2.py DORADO DORADO_ROS2 DDS_RECORDER"""
import json
import math
import os
import shutil
import signal
import struct
import subprocess
import sys
import tempfile
import time
import unittest

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "io"))
sys.path.insert(0, os.path.join(HERE, "..", "ros"))

DORADO, NODE, RECORDER = sys.argv[1:4]
RADAR = "/hugin_raf_1/radar_data"
IMU = "/imu/data"
ODOMETRY = ("/doppler_odom", "/dorado/map_odom", "/dorado/smoothed_odom")
SKIP = 77
# Localhost only: the loopback interface, unicast discovery.
LOCALHOST = ("<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
             "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
             "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>30"
             "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
             "</Domain></CycloneDDS>")


def read_tum(path):
    import ros_harness
    return ros_harness.read_tum(path)


def stamp_of(cdr):
    """A message's header stamp [ns] from its CDR bytes (int32 sec, uint32 nanosec after the
    encapsulation, little-endian)."""
    sec, nanosec = struct.unpack_from("<iI", cdr, 4)
    return sec * 1_000_000_000 + nanosec


def with_stamp(cdr, stamp_ns):
    out = bytearray(cdr)
    struct.pack_into("<iI", out, 4, stamp_ns // 1_000_000_000, stamp_ns % 1_000_000_000)
    return bytes(out)


def write_db3(path, messages):
    import rosbag2_writer as w
    writer = w.Db3Writer(path)
    for topic, type_name, t, data in messages:
        writer.write(topic, type_name, t, data)
    writer.close()


class Run:
    """One node run: its exit code, stderr, summary, and what the recorder received."""

    def __init__(self, code, err, summary, odometry, publications):
        self.code, self.err, self.summary = code, err, summary
        self.odometry, self.publications = odometry, publications

    def poses(self, topic):
        return {stamp: pose for t, stamp, pose in self.odometry if t == topic}

    def count(self, topic):
        return sum(1 for t, _, _ in self.odometry if t == topic)


class DoradoRos2(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.dir = tempfile.mkdtemp(prefix="dorado_ros2_test_")
        sim = os.path.join(cls.dir, "sim")
        subprocess.run([DORADO, "simulate", "--sequence", "seq04", "--duration", "6", "--out", sim],
                       check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        import make_ros2_bags
        cls.messages = [m for m in make_ros2_bags.ros1_messages(os.path.join(sim, "data.bag"))
                        if m[0] in (RADAR, IMU)]
        cls.recording = os.path.join(cls.dir, "data.db3")
        write_db3(cls.recording, cls.messages)
        cls.scans = sum(1 for m in cls.messages if m[0] == RADAR)
        with open(os.path.join(sim, "dataset.yaml")) as f:
            text = f.read()
        cls.dataset = os.path.join(sim, "dataset_ros2.yaml")
        with open(cls.dataset, "w") as f:
            f.write(text.replace("data.bag", cls.recording))
        subprocess.run([DORADO, "map", cls.dataset, "--out", os.path.join(cls.dir, "map")],
                       check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        cls.map = read_tum(os.path.join(cls.dir, "map", "trajectory.tum"))

    @classmethod
    def tearDownClass(cls):
        if os.environ.get("DORADO_KEEP_TEST_DIR") is None:
            shutil.rmtree(cls.dir, ignore_errors=True)

    def setUp(self):
        self.procs = []

    def tearDown(self):
        for p in self.procs:
            self.stop(p, 5)

    # --- processes -----------------------------------------------------------------------------
    def env(self, domain):
        env = dict(os.environ)
        env["ROS_DOMAIN_ID"] = str(domain)
        env.setdefault("CYCLONEDDS_URI", LOCALHOST)
        return env

    def start(self, cmd, name, domain):
        out = open(os.path.join(self.dir, name + ".out"), "w")
        err = open(os.path.join(self.dir, name + ".err"), "w")
        p = subprocess.Popen(cmd, stdout=out, stderr=err, env=self.env(domain),
                             start_new_session=True)
        p.log_paths = (out.name, err.name)
        self.procs.append(p)
        return p

    @staticmethod
    def stop(p, timeout_s=30):
        """SIGINT (a clean exit: the node publishes what its smoother holds), then SIGKILL."""
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGINT)
            try:
                p.wait(timeout_s)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        return p.returncode

    @staticmethod
    def wait_for(predicate, timeout_s, what):
        end = time.time() + timeout_s
        while time.time() < end:
            if predicate():
                return
            time.sleep(0.05)
        raise AssertionError(what)

    @staticmethod
    def text(path):
        with open(path) as f:
            return f.read()

    def start_node(self, name, domain, **params):
        params.setdefault("config", self.dataset)
        params.setdefault("summary_file", os.path.join(self.dir, name + ".json"))
        path = os.path.join(self.dir, name + "_params.yaml")
        with open(path, "w") as f:
            json.dump({"dorado_ros2": {"ros__parameters": params}}, f)  # JSON is YAML
        node = self.start([NODE, "--ros-args", "--params-file", path], name, domain)
        self.wait_for(lambda: node.poll() is not None or "; domain " in self.text(node.log_paths[1]),
                      30, f"{name}: dorado_ros2 did not start")
        self.assertIsNone(node.poll(), self.text(node.log_paths[1]))
        node.summary_path = params["summary_file"]
        return node

    def replay(self, name, domain, recording, rate, *extra, topics=(RADAR,)):
        cmd = [DORADO, "replay", recording, "--rate", str(rate), "--wait-subscribers", "10",
               "--topics", *topics, *extra]
        p = self.start(cmd, name, domain)
        p.wait(120)
        return p.returncode, self.text(p.log_paths[0]) + self.text(p.log_paths[1])

    def run_node(self, name, domain, recording, rate, replays=((),), topics=(RADAR,), expect=None,
                 **params):
        """The recorder and the node on `domain`, each replay (its extra arguments) in turn, then
        SIGINT to the node once the odometry stopped coming (or `expect` /doppler_odom)."""
        rec_dir = os.path.join(self.dir, name + "_rec")
        os.makedirs(rec_dir, exist_ok=True)
        recorder = self.start([RECORDER, rec_dir, *ODOMETRY], name + "_rec", domain)
        self.wait_for(lambda: "ready" in self.text(recorder.log_paths[0]), 30,
                      f"{name}: dds_recorder did not start")
        node = self.start_node(name, domain, **params)
        for i, extra in enumerate(replays):
            code, out = self.replay(f"{name}_replay{i}", domain, recording, rate, *extra,
                                    topics=topics)
            self.assertEqual(code, 0, out)
        odometry_file = os.path.join(rec_dir, "odometry.txt")
        count, last_change = -1, time.time()
        while time.time() - last_change < 2.0:
            n = sum(1 for line in open(odometry_file) if line.startswith("/doppler_odom "))
            if expect is not None and n >= expect:
                break
            if n != count:
                count, last_change = n, time.time()
            time.sleep(0.1)
        code = self.stop(node)
        time.sleep(0.3)
        self.stop(recorder)
        odometry = []
        for line in open(odometry_file):
            v = line.split()
            odometry.append((v[0], int(v[1]), tuple(float(x) for x in v[4:11])))
        publications = [line.split() for line in open(os.path.join(rec_dir, "publications.txt"))]
        with open(node.summary_path) as f:
            summary = json.load(f)
        return Run(code, self.text(node.log_paths[1]), summary, odometry, publications)

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
                                 with_stamp(data, stamp_of(data) - 50_000_000)))
        path = os.path.join(self.dir, "faults.db3")
        write_db3(path, messages)
        run = self.run_node("faults", 63, path, 2, expect=len(radar), queue_size=1000)
        print(f"faults: {len(radar)} scans + 2 duplicates + 3 older; dropped {run.summary['dropped']}")
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(run.summary["dropped"], {"duplicate stamp": 2, "out of order": 3})
        self.assertEqual(run.summary["published"], len(radar))
        self.assertEqual(run.err.count("duplicate stamp: dropped a scan"), 1, run.err)
        self.assertEqual(run.err.count("out of order: dropped a scan"), 1, run.err)

    def test_an_undecodable_cloud_is_one_clear_error(self):
        with open(self.dataset) as f:
            text = f.read()
        wrong = os.path.join(self.dir, "wrong_field.yaml")
        with open(wrong, "w") as f:
            f.write(text.replace("doppler: doppler", "doppler: dopler"))
        self.assertNotEqual(text, open(wrong).read(), "the simulated dataset names no doppler field")
        path = os.path.join(self.dir, "short.db3")
        radar = [m for m in self.messages if m[0] == RADAR][:20]
        write_db3(path, radar)
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
        write_db3(path, kept)
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

    def test_ros_domain_id_is_honoured(self):
        other = self.start_node("other_domain", 68)
        run = self.run_node("domain", 67, self.recording, 5, queue_size=1000)
        self.assertEqual(run.code, 0, run.err)
        self.assertEqual(self.stop(other), 0)
        with open(other.summary_path) as f:
            other_summary = json.load(f)
        print(f"domains: node on 67 received {run.summary['received']}, node on 68 "
              f"{other_summary['received']}")
        self.assertEqual(run.summary["received"], self.scans)
        self.assertEqual(other_summary["received"], 0)
        bad = subprocess.run([NODE], env=dict(self.env(0), ROS_DOMAIN_ID="abc"),
                             capture_output=True, text=True, timeout=30)
        self.assertEqual(bad.returncode, 1)
        self.assertIn("ROS_DOMAIN_ID='abc'", bad.stderr)


if __name__ == "__main__":
    try:
        import rosbag  # noqa: F401  (the simulator's bag is converted with python3-rosbag)
    except ImportError as e:
        print(f"dorado_ros2 tests skipped: python3-rosbag missing ({e})")
        sys.exit(SKIP)
    unittest.main(argv=sys.argv[:1], verbosity=2, warnings="ignore")

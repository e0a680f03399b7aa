"""dorado_ros2 over DDS on localhost, without ROS 2, for its tests and latency benchmark: a
simulated recording as rosbag2, the node, `dorado replay` and dds_recorder (a DDS subscriber
that decodes with the rosbag2 reader's codec), each on a ROS_DOMAIN_ID of the caller's. Every
process started here is stopped (SIGINT, then SIGKILL) by Dds.close(), also on failure."""
import json
import os
import struct
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, os.path.join(HERE, "..", "io"))
sys.path.insert(0, os.path.join(HERE, "..", "ros"))
import ros_harness  # noqa: E402  (processes stopped and waited for, TUM files read as for ROS1)
from ros_harness import read_tum  # noqa: E402

RADAR = "/hugin_raf_1/radar_data"
IMU = "/imu/data"
ODOMETRY = ("/doppler_odom", "/dorado/map_odom", "/dorado/smoothed_odom")
SKIP = 77  # ctest SKIP_RETURN_CODE
# Localhost only: the loopback interface, unicast discovery.
LOCALHOST = ("<CycloneDDS><Domain Id=\"any\"><General><Interfaces><NetworkInterface name=\"lo\"/>"
             "</Interfaces><AllowMulticast>false</AllowMulticast></General><Discovery>"
             "<ParticipantIndex>auto</ParticipantIndex><MaxAutoParticipantIndex>30"
             "</MaxAutoParticipantIndex><Peers><Peer address=\"127.0.0.1\"/></Peers></Discovery>"
             "</Domain></CycloneDDS>")


def missing():
    """Why the recording cannot be made here (None when it can)."""
    try:
        import rosbag  # noqa: F401  (the simulator's bag is converted with python3-rosbag)
    except ImportError as e:
        return f"python3-rosbag missing ({e}); run with /usr/bin/python3"
    return None




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




class Recording:
    """`dorado simulate --sequence seq04` for `seconds`, its recording as a rosbag2 .db3
    (tests/io/make_ros2_bags.py's conversion), a dataset YAML on it, and `dorado map`'s
    trajectory of it."""

    def __init__(self, dorado, work_dir, seconds):
        sim = os.path.join(work_dir, "sim")
        subprocess.run([dorado, "simulate", "--sequence", "seq04", "--duration", str(seconds),
                        "--out", sim], check=True, stderr=subprocess.DEVNULL,
                       stdout=subprocess.DEVNULL)
        import make_ros2_bags
        self.messages = list(make_ros2_bags.ros1_messages(os.path.join(sim, "data.bag")))
        self.path = os.path.join(work_dir, "data.db3")
        write_db3(self.path, self.messages)
        self.scans = sum(1 for m in self.messages if m[0] == RADAR)
        with open(os.path.join(sim, "dataset.yaml")) as f:
            text = f.read()
        self.dataset = os.path.join(sim, "dataset_ros2.yaml")
        with open(self.dataset, "w") as f:
            f.write(text.replace("data.bag", self.path))
        subprocess.run([dorado, "map", self.dataset, "--accept-implausible", "--out", os.path.join(work_dir, "map")],
                       check=True, stderr=subprocess.DEVNULL, stdout=subprocess.DEVNULL)
        self.map = read_tum(os.path.join(work_dir, "map", "trajectory.tum"))


class Dds:
    """The processes of one test: started on a domain each, stopped by close()."""

    def __init__(self, work_dir, dorado, node, recorder):
        self.dir, self.dorado, self.node, self.recorder = work_dir, dorado, node, recorder
        self.procs = []

    def close(self):
        for p in reversed(self.procs):
            self.stop(p, 5)
        self.procs = []

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

    # SIGINT (a clean exit: the node publishes what its smoother holds), then SIGKILL.
    stop = staticmethod(ros_harness.Graph.stop)
    wait_for = staticmethod(ros_harness.Graph.wait_for)

    @staticmethod
    def text(path):
        with open(path) as f:
            return f.read()

    def start_node(self, name, domain, ros_args=(), **params):
        """dorado_ros2 with `params` in a --params-file (ROS 2's layout) and `ros_args` after it,
        up and subscribed."""
        params.setdefault("summary_file", os.path.join(self.dir, name + ".json"))
        path = os.path.join(self.dir, name + "_params.yaml")
        with open(path, "w") as f:
            json.dump({"dorado_ros2": {"ros__parameters": params}}, f)  # JSON is YAML
        node = self.start([self.node, "--ros-args", "--params-file", path, *ros_args], name, domain)
        self.wait_for(lambda: node.poll() is not None or "; domain " in self.text(node.log_paths[1]),
                      30, f"{name}: dorado_ros2 did not start")
        if node.poll() is not None:
            raise AssertionError(f"{name}: dorado_ros2 exited: {self.text(node.log_paths[1])}")
        node.summary_path = params["summary_file"]
        return node

    def replay(self, name, domain, recording, rate, *extra, topics=(RADAR,)):
        """`dorado replay` until it ends: (exit code, its output)."""
        cmd = [self.dorado, "replay", recording, "--rate", str(rate), "--wait-subscribers", "10",
               "--topics", *topics, *extra]
        p = self.start(cmd, name, domain)
        p.wait(300)
        return p.returncode, self.text(p.log_paths[0]) + self.text(p.log_paths[1])

    def run_node(self, name, domain, recording, rate, replays=((),), topics=(RADAR,), expect=None,
                 ros_args=(), **params):
        """The recorder and the node on `domain`, each replay (its extra arguments) in turn, then
        SIGINT to the node once the odometry stopped coming (or `expect` /doppler_odom)."""
        rec_dir = os.path.join(self.dir, name + "_rec")
        os.makedirs(rec_dir, exist_ok=True)
        recorder = self.start([self.recorder, rec_dir, *ODOMETRY], name + "_rec", domain)
        self.wait_for(lambda: "ready" in self.text(recorder.log_paths[0]), 30,
                      f"{name}: dds_recorder did not start")
        node = self.start_node(name, domain, ros_args, **params)
        for i, extra in enumerate(replays):
            code, out = self.replay(f"{name}_replay{i}", domain, recording, rate, *extra,
                                    topics=topics)
            if code != 0:
                raise AssertionError(f"{name}: dorado replay exit {code}: {out}")
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

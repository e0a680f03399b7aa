"""A real ROS1 graph for dorado_ros's tests and latency benchmark: a rosmaster on a free port with
its own ROS_MASTER_URI, dorado_ros, `rosbag play`, and an in-process rospy recorder. Every
process started here is stopped (SIGINT, then SIGKILL) by Graph.close(), also on failure."""
import os
import signal
import socket
import subprocess
import tempfile
import time

SKIP = 77  # ctest SKIP_RETURN_CODE


def ros_missing():
    """Why the tests cannot run here (None when ROS1 is present)."""
    for tool in ("rosmaster", "rosbag"):
        if not any(os.access(os.path.join(d, tool), os.X_OK)
                   for d in os.environ.get("PATH", "").split(os.pathsep)):
            return f"{tool} not found (install ros-core and python3-rosbag)"
    try:
        import rospy  # noqa: F401
        import rosbag  # noqa: F401
    except ImportError as e:
        return f"python ROS modules missing ({e}); run with /usr/bin/python3"
    return None


def free_port():
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def read_tum(path):
    """{stamp_ns: (x, y, z, qx, qy, qz, qw)} from a TUM file."""
    poses = {}
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = line.split()
            sec, frac = v[0].split(".") if "." in v[0] else (v[0], "0")
            stamp_ns = int(sec) * 10**9 + int((frac + "000000000")[:9])
            poses[stamp_ns] = tuple(float(x) for x in v[1:8])
    return poses


class Graph:
    """A rosmaster on a free port, and the processes started on it."""

    def __init__(self, work_dir):
        self.work_dir = work_dir
        self.port = free_port()
        self.env = dict(os.environ)
        self.env["ROS_MASTER_URI"] = f"http://127.0.0.1:{self.port}"
        self.env["ROS_HOSTNAME"] = "127.0.0.1"
        self.env["ROS_LOG_DIR"] = os.path.join(work_dir, "ros_log")
        self.env["ROS_HOME"] = os.path.join(work_dir, "ros_home")
        self.procs = []
        os.environ.update({k: self.env[k] for k in ("ROS_MASTER_URI", "ROS_HOSTNAME",
                                                     "ROS_LOG_DIR", "ROS_HOME")})
        self.master = self.start(["rosmaster", "--core", "-p", str(self.port)], "rosmaster")
        self.wait_for(lambda: self._master_up(), 15, "rosmaster did not come up")

    def _master_up(self):
        import rosgraph
        return rosgraph.Master("/dorado_test").is_online()

    def start(self, cmd, name, extra_env=None):
        out = open(os.path.join(self.work_dir, name + ".out"), "w")
        err = open(os.path.join(self.work_dir, name + ".err"), "w")
        env = dict(self.env, **(extra_env or {}))
        p = subprocess.Popen(cmd, stdout=out, stderr=err, env=env, start_new_session=True)
        p.log_paths = (out.name, err.name)
        self.procs.append(p)
        return p

    @staticmethod
    def wait_for(predicate, timeout_s, what):
        end = time.time() + timeout_s
        while time.time() < end:
            try:
                if predicate():
                    return
            except Exception:  # the master or a topic not there yet
                pass
            time.sleep(0.1)
        raise AssertionError(what)

    def publishes(self, topic):
        import rosgraph
        pubs, _, _ = rosgraph.Master("/dorado_test").getSystemState()
        return any(t == topic and nodes for t, nodes in pubs)

    def subscribes(self, topic):
        import rosgraph
        _, subs, _ = rosgraph.Master("/dorado_test").getSystemState()
        return any(t == topic and nodes for t, nodes in subs)

    @staticmethod
    def stop(p, timeout_s=20):
        """SIGINT (a clean exit), then SIGKILL; returns the exit code."""
        if p.poll() is None:
            os.killpg(p.pid, signal.SIGINT)
            try:
                p.wait(timeout_s)
            except subprocess.TimeoutExpired:
                os.killpg(p.pid, signal.SIGKILL)
                p.wait()
        return p.returncode

    def close(self):
        for p in reversed(self.procs):
            self.stop(p, 10)
        self.procs = []


def node_command(dorado_ros, params):
    return [dorado_ros] + [f"_{k}:={v}" for k, v in params.items()]


class Recorder:
    """Records nav_msgs/Odometry topics in this process (rospy, initialised once)."""

    def __init__(self, topics):
        import rospy
        from nav_msgs.msg import Odometry
        rospy.init_node("dorado_test_recorder", anonymous=True, disable_signals=True)
        self.messages = {t: [] for t in topics}
        self.subs = [rospy.Subscriber(t, Odometry, self._on, callback_args=t, queue_size=10000)
                     for t in topics]
        # TF as tf2 composes it: every /tf transform into a fresh buffer per run (clear()).
        import tf2_ros
        from tf2_msgs.msg import TFMessage
        self._tf2_ros = tf2_ros
        self.tf = tf2_ros.Buffer(cache_time=rospy.Duration(3600))
        self.tf_sub = rospy.Subscriber("/tf", TFMessage, self._on_tf, queue_size=10000)

    def _on(self, msg, topic):
        p, q = msg.pose.pose.position, msg.pose.pose.orientation
        self.messages[topic].append((msg.header.stamp.to_nsec(), (p.x, p.y, p.z, q.x, q.y, q.z, q.w),
                                     tuple(msg.pose.covariance), tuple(msg.twist.covariance)))

    def _on_tf(self, msg):
        for t in msg.transforms:
            self.tf.set_transform(t, "dorado_test_recorder")

    def lookup(self, target, source, stamp_ns):
        """The pose of `source` in `target` at the stamp, composed by tf2 (x y z qx qy qz qw)."""
        import rospy
        t = self.tf.lookup_transform(target, source, rospy.Time(0, stamp_ns)).transform
        return (t.translation.x, t.translation.y, t.translation.z,
                t.rotation.x, t.rotation.y, t.rotation.z, t.rotation.w)

    def clear(self):
        for t in self.messages:
            self.messages[t] = []
        self.tf = self._tf2_ros.Buffer(cache_time=__import__("rospy").Duration(3600))

    def connected(self, topics):
        return all(s.get_num_connections() > 0 for s in self.subs if s.name in topics)


def run_node_on_bag(graph, recorder, dorado_ros, params, bag, rate, name, topics=("/doppler_odom",),
                    expect=None, timeout_s=120):
    """Starts dorado_ros, waits until it is connected, plays the bag at `rate`, waits for the last
    messages (`expect` of them on topics[0], or none new for 3 s), stops the node with SIGINT. Returns (exit code, node stderr text)."""
    recorder.clear()
    # A node name per run: private parameters stay on the parameter server after a node exits.
    node = graph.start(node_command(dorado_ros, params) + [f"__name:=dorado_ros_{name}"], name)
    input_topic = params.get("input_topic", "/hugin_raf_1/radar_data")
    graph.wait_for(lambda: node.poll() is None and graph.subscribes(input_topic)
                   and recorder.connected(topics), 30, f"{name}: dorado_ros did not connect")
    play = graph.start(["rosbag", "play", "-q", "-d", "1", "-r", str(rate), bag], name + "_play")
    play.wait(timeout_s)
    # The scans still queued through the pipeline: until `expect` messages, or none for 3 s.
    topic, count, last_change = topics[0], -1, time.time()
    while time.time() - last_change < 3.0 and time.time() - last_change < timeout_s:
        n = len(recorder.messages[topic])
        if expect is not None and n >= expect:
            break
        if n != count:
            count, last_change = n, time.time()
        time.sleep(0.1)
    time.sleep(0.3)
    code = graph.stop(node)
    with open(node.log_paths[1]) as f:
        err = f.read()
    with open(node.log_paths[0]) as f:
        err += f.read()
    return code, err


def misspelled_doppler_field(dataset, out_path):
    """A copy of the dataset YAML whose field map names a Doppler field no message has."""
    with open(dataset) as f:
        text = f.read()
    wrong = text.replace("doppler: doppler", "doppler: dopler")
    if wrong == text:
        raise AssertionError(f"{dataset} names no doppler field")
    with open(out_path, "w") as f:
        f.write(wrong)
    return out_path


def work_dir(prefix):
    return tempfile.mkdtemp(prefix=prefix)

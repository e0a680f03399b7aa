#!/usr/bin/python3
"""Writes Hugin-layout bags with known faults at known scan indices, for the end-to-end fault tests
of `dorado odometry`, `dorado map` and `dorado info` (test_cmd_faults.cpp).

The vehicle (base frame = rear-axle centre) drives a flat circle with a constant twist
v_base = (SPEED, 0, 0), omega = (0, 0, YAW_RATE) from the first scan on, through a static world of
random landmarks (so scan-to-map registration has something to register), plus MOVING random
points per scan. The vehicle keeps moving through the gap: the truth is the same constant twist.

OUT_DIR/faults/: SCANS radar messages at RATE Hz (indices are radar message indices, as dorado
counts them), IMU at 100 Hz except during the gap:
  NAN_SCANS      every point NaN (x, y, z, doppler)
  EMPTY_SCAN     width 0
  BACKWARD_SCAN  header stamp BACKWARD_S before the previous scan's (record time in order)
  POINT_STEP_SCAN  point_step 40 and row_step 40 * width for 32-byte points: data too short
  ROW_STEP_SCAN    2 rows whose row_step is 1.5 x the real one: data too short for the 2nd row
  GAP_AFTER      GAP_S more seconds (no scan, no IMU) before the next scan
OUT_DIR/empty_topics/: GOOD_SCANS good scans; the IMU topic and the ground-truth topic are
  registered in the bag (a connection record) but hold zero messages.
OUT_DIR/absent_topic.yaml: the faults bag with imu_topic naming a topic the bag does not have.
Usage: make_fault_bag.py OUT_DIR
"""
import math
import os
import random
import struct
import sys

import rosbag
import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import Imu, PointCloud2, PointField

# The same vehicle and mounts as the odometry test bag, and its dataset description.
from make_odometry_bag import RADAR_YAW_DEG, S_X, S_Y, S_Z, dataset_yaml, rot_z

SPEED, YAW_RATE = 2.0, 0.15
RATE, N_STATIC, N_MOVING, LANDMARKS = 10.0, 360, 40, 2500
T0 = 1700000000
RADAR, IMU, GT = "/hugin_raf_1/radar_data", "/imu/data", "/ground_truth/odom"

SCANS = 90
NAN_SCANS = (20, 35)
EMPTY_SCAN = 25
BACKWARD_SCAN, BACKWARD_S = 30, 0.05
POINT_STEP_SCAN = 40
ROW_STEP_SCAN = 45
GAP_AFTER, GAP_S = 59, 10.0
GOOD_SCANS = 30


def scan_time(k):  # seconds after the first scan
    return k / RATE + (GAP_S if k > GAP_AFTER else 0.0)


def true_pose(t):
    """Base pose in the world after t s of the constant twist: (x, y, yaw)."""
    yaw = YAW_RATE * t
    r = SPEED / YAW_RATE
    return r * math.sin(yaw), r * (1.0 - math.cos(yaw)), yaw


def world(rng):
    return [(rng.uniform(-70, 70), rng.uniform(-60, 80), rng.uniform(-1.0, 4.0))
            for _ in range(LANDMARKS)]


def visible(d_radar):
    """Range, elevation, azimuth of a radar-frame point, or None outside the field of view."""
    r = math.sqrt(sum(c * c for c in d_radar))
    if not 2.0 <= r <= 60.0:
        return None
    az, el = math.atan2(d_radar[1], d_radar[0]), math.asin(d_radar[2] / r)
    if abs(az) > math.radians(60) or abs(el) > math.radians(15):
        return None
    return r, el, az


def scan_points(rng, landmarks, t):
    """Packed 32-byte points (x y z range elevation azimuth power doppler) seen at time t."""
    x, y, yaw = true_pose(t)
    radar_yaw = yaw + math.radians(RADAR_YAW_DEG)
    s_world = rot_z(yaw, (S_X, S_Y, S_Z))
    radar_pos = (x + s_world[0], y + s_world[1], s_world[2])
    # v_s (base) = v_base + omega x S; omega x S = (-w S_y, w S_x, 0); then into the radar frame.
    v_s_base = (SPEED - YAW_RATE * S_Y, YAW_RATE * S_X, 0.0)
    v_radar = rot_z(-math.radians(RADAR_YAW_DEG), v_s_base)
    points = []
    for p in landmarks:
        rel = (p[0] - radar_pos[0], p[1] - radar_pos[1], p[2] - radar_pos[2])
        q = rot_z(-radar_yaw, rel)
        if visible(q) is not None:
            points.append(q)
    points = rng.sample(points, min(N_STATIC, len(points)))
    data = b""
    for i in range(len(points) + N_MOVING):
        u = (0.0, 0.0, 0.0)
        if i < len(points):
            q = points[i]
        else:  # a car crossing, anywhere in the field of view
            az, el = math.radians(rng.uniform(-60, 60)), math.radians(rng.uniform(-15, 15))
            r = rng.uniform(2, 60)
            q = (r * math.cos(el) * math.cos(az), r * math.cos(el) * math.sin(az), r * math.sin(el))
            u = (-6.0, 3.0, 0.0)
        r, el, az = visible(q)
        d = (q[0] / r, q[1] / r, q[2] / r)
        doppler = sum(d[j] * (u[j] - v_radar[j]) for j in range(3)) + rng.gauss(0, 0.03)
        data += struct.pack("<8f", q[0], q[1], q[2], r, el, az, rng.uniform(5, 40), doppler)
    return data


def cloud(stamp, data, width, height=1, point_step=32, row_step=None):
    names = ["x", "y", "z", "range", "elevation", "azimuth", "power", "doppler"]
    msg = PointCloud2()
    msg.header.stamp = stamp
    msg.header.frame_id = "radar"
    msg.height, msg.width = height, width
    msg.fields = [PointField(n, 4 * j, PointField.FLOAT32, 1) for j, n in enumerate(names)]
    msg.point_step = point_step
    msg.row_step = point_step * width if row_step is None else row_step
    msg.data = data
    return msg


def write_imu(bag, t_s):
    t = rospy.Time.from_sec(T0 + t_s)
    imu = Imu()
    imu.header.stamp = t
    w_imu = rot_z(-math.pi / 2, (0.0, 0.0, YAW_RATE))  # IMU frame rotated +90 deg about Z
    imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = w_imu
    imu.linear_acceleration.z = 9.81
    bag.write(IMU, imu, t)


def fault_scan(rng, landmarks, k):
    """The PointCloud2 of scan k of the faults bag."""
    stamp = rospy.Time.from_sec(T0 + 0.05 + scan_time(k))
    data = scan_points(rng, landmarks, scan_time(k))
    n = len(data) // 32
    if k in NAN_SCANS:
        return cloud(stamp, struct.pack("<8f", *[float("nan")] * 8) * n, n)
    if k == EMPTY_SCAN:
        return cloud(stamp, b"", 0)
    if k == BACKWARD_SCAN:
        earlier = rospy.Time.from_sec(T0 + 0.05 + scan_time(k - 1) - BACKWARD_S)
        return cloud(earlier, data, n)
    if k == POINT_STEP_SCAN:
        return cloud(stamp, data, n, point_step=40)
    if k == ROW_STEP_SCAN:
        half = n // 2
        return cloud(stamp, data[: 2 * half * 32], half, height=2, row_step=48 * half)
    return cloud(stamp, data, n)


def write_faults(out_dir, rng, landmarks):
    with rosbag.Bag(os.path.join(out_dir, "data.bag"), "w") as bag:
        gap = (scan_time(GAP_AFTER), scan_time(GAP_AFTER + 1))
        for j in range(int(scan_time(SCANS - 1) * 100) + 10):  # IMU at 100 Hz, none in the gap
            if not gap[0] + 0.05 < j * 0.01 < gap[1] + 0.05:
                write_imu(bag, j * 0.01)
        for k in range(SCANS):
            record = rospy.Time.from_sec(T0 + 0.05 + scan_time(k))  # the bag's order stays right
            bag.write(RADAR, fault_scan(rng, landmarks, k), record)


def register_without_messages(bag, topic, msg_class):
    """A connection record for `topic` with no message on it (`rosbag info` lists the topic with
    0 msgs). python rosbag's public API writes a connection only with a message, so this fills its
    private tables; close() then writes the connection record into the bag's index."""
    header = {"topic": topic, "type": msg_class._type, "md5sum": msg_class._md5sum,
              "message_definition": msg_class._full_text}
    info = rosbag.bag._ConnectionInfo(len(bag._connections), topic, header)
    bag._connections[info.id] = info
    bag._topic_connections[topic] = info


def write_empty_topics(out_dir, rng, landmarks):
    with rosbag.Bag(os.path.join(out_dir, "data.bag"), "w") as bag:
        for k in range(GOOD_SCANS):
            stamp = rospy.Time.from_sec(T0 + 0.05 + k / RATE)
            data = scan_points(rng, landmarks, k / RATE)
            bag.write(RADAR, cloud(stamp, data, len(data) // 32), stamp)
        register_without_messages(bag, IMU, Imu)
        register_without_messages(bag, GT, Odometry)


def main(out_dir):
    rng = random.Random(11)
    landmarks = world(rng)
    for name in ("faults", "empty_topics"):
        os.makedirs(os.path.join(out_dir, name), exist_ok=True)
    write_faults(os.path.join(out_dir, "faults"), rng, landmarks)
    write_empty_topics(os.path.join(out_dir, "empty_topics"), rng, landmarks)
    with open(os.path.join(out_dir, "faults", "dataset.yaml"), "w") as f:
        f.write(dataset_yaml("faults", "data.bag", IMU))
    with open(os.path.join(out_dir, "empty_topics", "dataset.yaml"), "w") as f:
        f.write(dataset_yaml("empty_topics", "data.bag", IMU, GT))
    with open(os.path.join(out_dir, "absent_topic.yaml"), "w") as f:
        f.write(dataset_yaml("absent_topic", "faults/data.bag", "/imu/absent"))


if __name__ == "__main__":
    main(sys.argv[1])

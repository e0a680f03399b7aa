#!/usr/bin/python3
"""Writes a small Hugin-layout bag of a vehicle driving a flat circle with a known constant twist,
for the end-to-end tests of `dorado odometry` and `dorado calibrate`.

Vehicle (base frame = rear-axle centre): v_base = (SPEED, 0, 0), omega = (0, 0, YAW_RATE).
Radar at S = (S_X, S_Y, S_Z), rotated by yaw RADAR_YAW_DEG; IMU rotated by 90 deg about Z.
Each scan: N points in the radar's field of view, 20 % moving, Doppler = d.(u - v_radar) + noise.
Scan 30 has NaN Doppler everywhere (unusable: the odometry must fall back and say so).
Usage: make_odometry_bag.py OUT_DIR
"""
import math
import os
import random
import struct
import sys

import rosbag
import rospy
from sensor_msgs.msg import Imu, PointCloud2, PointField

SPEED, YAW_RATE = 2.0, 0.4
S_X, S_Y, S_Z = 0.9, 0.1, 0.6
HALF_WHEELBASE = 0.256
RADAR_YAW_DEG = 10.0
SCANS, N, RATE = 60, 400, 10.0
T0 = 1700000000


def rot_z(a, v):
    c, s = math.cos(a), math.sin(a)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


def dataset_yaml(name, bag, imu_topic, gt_topic=""):
    """The dataset description of a bag written with this mount (also used by make_fault_bag.py)."""
    gt = f"\n  ground_truth_topic: {gt_topic}" if gt_topic else ""
    return f"""name: {name}
reader: rosbag
rosbag:
  path: {bag}
  radar_topic: /hugin_raf_1/radar_data
  imu_topic: {imu_topic}{gt}
extrinsics:
  T_base_radar:
    translation_m: [{S_X}, {S_Y}, {S_Z}]
    rotation_rpy_deg: [0.0, 0.0, {RADAR_YAW_DEG}]
  T_base_imu:
    translation_m: [0.2, 0.0, 0.3]
    rotation_rpy_deg: [0.0, 0.0, 90.0]
vehicle:
  half_wheelbase_m: {HALF_WHEELBASE}
"""


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(7)
    # v_s (base) = v_base + omega x S; omega x S = (-w S_y, w S_x, 0)
    v_s_base = (SPEED - YAW_RATE * S_Y, YAW_RATE * S_X, 0.0)
    v_radar = rot_z(-math.radians(RADAR_YAW_DEG), v_s_base)  # R_base_radar^T v_s
    names = ["x", "y", "z", "range", "elevation", "azimuth", "power", "doppler"]
    with rosbag.Bag(os.path.join(out_dir, "data.bag"), "w") as bag:
        for k in range(int(SCANS / RATE * 100) + 1):  # IMU at 100 Hz, frame rotated +90 deg about Z
            t = rospy.Time.from_sec(T0 + k * 0.01)
            imu = Imu()
            imu.header.stamp = t
            w_imu = rot_z(-math.pi / 2, (0.0, 0.0, YAW_RATE))
            imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = w_imu
            imu.linear_acceleration.z = 9.81
            bag.write("/imu/data", imu, t)
        for k in range(SCANS):
            t = rospy.Time.from_sec(T0 + 0.05 + k / RATE)
            data = b""
            for i in range(N):
                az = math.radians(rng.uniform(-60, 60))
                el = math.radians(rng.uniform(-15, 15))
                d = (math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el))
                r = rng.uniform(2, 60)
                power = rng.uniform(5, 40)
                u = (0.0, 0.0, 0.0)
                if i < N // 5:
                    u = (-6.0, 3.0, 0.0)  # a car crossing
                doppler = sum(d[j] * (u[j] - v_radar[j]) for j in range(3)) + rng.gauss(0, 0.03)
                if k == 30:
                    doppler = float("nan")
                data += struct.pack("<8f", r * d[0], r * d[1], r * d[2], r, el, az, power, doppler)
            msg = PointCloud2()
            msg.header.stamp = t
            msg.header.frame_id = "radar"
            msg.height, msg.width = 1, N
            msg.fields = [PointField(n, 4 * j, PointField.FLOAT32, 1) for j, n in enumerate(names)]
            msg.point_step, msg.row_step = 32, 32 * N
            msg.data = data
            bag.write("/hugin_raf_1/radar_data", msg, t)
    with open(os.path.join(out_dir, "dataset.yaml"), "w") as f:
        f.write(dataset_yaml("odometry_e2e", "data.bag", "/imu/data"))
    with open(os.path.join(out_dir, "truth.txt"), "w") as f:
        f.write(f"{SPEED} {YAW_RATE} {S_X}\n")


if __name__ == "__main__":
    main(sys.argv[1])

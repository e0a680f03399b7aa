#!/usr/bin/python3
"""Writes a bag mounted as the paper's Hugin (its launch file's sensor_pose, calib_rot and
sensor_to_icr_x), in the Hugin layout on /hugin_raf_1/radar_data, for the bare-bag test
(`dorado odometry data.bag` with no dataset description).

The mount, computed here from the launch values without dorado's code: R_base_radar =
R(calib_rot) R(sensor_rot), the radar at (-sensor_to_icr_x, 0.22, 0.17) from the ICR point.
The vehicle (the ICR point) moves with a constant twist: v_base = (SPEED, 0, 0), omega = (0,
PITCH_RATE, YAW_RATE); Doppler = d.(u - v_radar) + noise, 20 % of the points moving.
Usage: make_hugin_mount_bag.py OUT_DIR   (writes OUT_DIR/data.bag and OUT_DIR/truth.txt)
"""
import math
import os
import random
import struct
import sys

import rosbag
import rospy
from sensor_msgs.msg import PointCloud2, PointField

SENSOR_POSE = [0.85, 0.22, 0.17, 0.6857716483037417, 0.7276229492792916, 0.012222542255175764,
               0.011519528015294512]
CALIB_ROT = [-0.00295514, -0.01095426, 0.01718881, 0.99978789]
SENSOR_TO_ICR_X = -0.9944683540059478
SPEED, PITCH_RATE, YAW_RATE = 1.5, 0.05, 0.3
SCANS, N, RATE = 50, 400, 10.0
T0 = 1700000000


def quat_to_matrix(q):
    x, y, z, w = q
    n = math.sqrt(x * x + y * y + z * z + w * w)
    x, y, z, w = x / n, y / n, z / n, w / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def matmul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(m):
    return [[m[j][i] for j in range(3)] for i in range(3)]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]


def main(out_dir):
    os.makedirs(out_dir, exist_ok=True)
    rng = random.Random(11)
    R_base_radar = matmul(quat_to_matrix(CALIB_ROT), quat_to_matrix(SENSOR_POSE[3:]))
    s = [-SENSOR_TO_ICR_X, SENSOR_POSE[1], SENSOR_POSE[2]]
    omega = [0.0, PITCH_RATE, YAW_RATE]
    v_s_base = [a + b for a, b in zip([SPEED, 0.0, 0.0], cross(omega, s))]
    v_radar = apply(transpose(R_base_radar), v_s_base)
    names = ["x", "y", "z", "range", "azimuth", "elevation", "power", "doppler"]
    with rosbag.Bag(os.path.join(out_dir, "data.bag"), "w") as bag:
        for k in range(SCANS):
            t = rospy.Time.from_sec(T0 + k / RATE)
            data = b""
            for i in range(N):
                az = math.radians(rng.uniform(-60, 60))
                el = math.radians(rng.uniform(-15, 15))
                d_base = [math.cos(el) * math.cos(az), math.cos(el) * math.sin(az), math.sin(el)]
                d = apply(transpose(R_base_radar), d_base)  # forward-looking, in the radar frame
                r = rng.uniform(2, 60)
                u = [0.0, 0.0, 0.0] if i >= N // 5 else apply(transpose(R_base_radar), [-5, 2, 0])
                doppler = sum(d[j] * (u[j] - v_radar[j]) for j in range(3)) + rng.gauss(0, 0.03)
                data += struct.pack("<8f", r * d[0], r * d[1], r * d[2], r, az, el,
                                    rng.uniform(5, 40), doppler)
            msg = PointCloud2()
            msg.header.stamp = t
            msg.header.frame_id = "hugin_raf_1"
            msg.height, msg.width = 1, N
            msg.fields = [PointField(n, 4 * j, PointField.FLOAT32, 1) for j, n in enumerate(names)]
            msg.point_step, msg.row_step = 32, 32 * N
            msg.data = data
            bag.write("/hugin_raf_1/radar_data", msg, t)
    with open(os.path.join(out_dir, "truth.txt"), "w") as f:
        f.write(f"{SPEED} {PITCH_RATE} {YAW_RATE}\n")


if __name__ == "__main__":
    main(sys.argv[1])

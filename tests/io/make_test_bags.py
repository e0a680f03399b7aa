#!/usr/bin/python3
"""Writes small ROS1 bags with known content using the real ROS tools (Debian's python3-rosbag).

Point i of scan k has the values of expected_point(k, i); the C++ test computes the same formula.
Usage: make_test_bags.py OUT_DIR
"""
import os
import struct
import sys

import rosbag
import rospy
from geometry_msgs.msg import PoseStamped
from nav_msgs.msg import Odometry
from sensor_msgs.msg import ChannelFloat32, Imu, PointCloud, PointCloud2, PointField
from geometry_msgs.msg import Point32

N_POINTS = 12
N_SCANS = 5
T0 = 1690000000  # seconds


def expected_point(k, i):
    """x, y, z, range, elevation, azimuth, power, doppler (exact in float32)."""
    return (0.5 * i + k, -0.25 * i, 0.125 * i - 1.0, 2.0 + i, 0.01 * i, -0.02 * i, 10.0 + i, 0.1 * i - 0.5)


def stamp(k):
    return rospy.Time(T0 + k // 10, (k % 10) * 100_000_000 + 123)


def hugin_cloud(k, big_endian=False):
    names = ["x", "y", "z", "range", "elevation", "azimuth", "power", "doppler"]
    msg = PointCloud2()
    msg.header.stamp = stamp(k)
    msg.header.frame_id = "radar"
    msg.height, msg.width = 1, N_POINTS
    msg.fields = [PointField(n, 4 * j, PointField.FLOAT32, 1) for j, n in enumerate(names)]
    msg.is_bigendian = big_endian
    msg.point_step, msg.row_step = 32, 32 * N_POINTS
    fmt = (">" if big_endian else "<") + "8f"
    msg.data = b"".join(struct.pack(fmt, *expected_point(k, i)) for i in range(N_POINTS))
    msg.is_dense = True
    return msg


def float64_cloud(k):
    """Other names, float64 and int16, a padded point_step and padded rows, 2 rows."""
    msg = PointCloud2()
    msg.header.stamp = stamp(k)
    msg.header.frame_id = "radar"
    msg.height, msg.width = 2, N_POINTS // 2
    msg.fields = [PointField("px", 0, PointField.FLOAT64, 1), PointField("py", 8, PointField.FLOAT64, 1),
                  PointField("pz", 16, PointField.FLOAT64, 1), PointField("vr", 24, PointField.FLOAT64, 1),
                  PointField("rcs", 32, PointField.INT16, 1)]
    msg.point_step = 40
    msg.row_step = 40 * msg.width + 8
    data = b""
    for row in range(2):
        for col in range(msg.width):
            x, y, z, _, _, _, p, d = expected_point(k, row * msg.width + col)
            data += struct.pack("<4dh6x", x, y, z, d, int(p))
        data += b"\xee" * 8
    msg.data = data
    return msg


def channel_cloud(k):
    msg = PointCloud()
    msg.header.stamp = stamp(k)
    msg.header.frame_id = "radar"
    pts = [expected_point(k, i) for i in range(N_POINTS)]
    msg.points = [Point32(p[0], p[1], p[2]) for p in pts]
    msg.channels = [ChannelFloat32("Doppler", [p[7] for p in pts]), ChannelFloat32("Power", [p[6] for p in pts])]
    return msg


def write(path, make_cloud, topic="/hugin_raf_1/radar_data", extras=True, nan_scan=None, backwards=False):
    with rosbag.Bag(path, "w") as bag:
        for k in range(N_SCANS):
            msg = make_cloud(k)
            if nan_scan == k:
                msg.data = bytearray(msg.data)
                msg.data[0:4] = struct.pack("<f", float("nan"))
                msg.data = bytes(msg.data)
            t = stamp(k)
            if backwards and k == 3:
                msg.header.stamp = stamp(1)
            bag.write(topic, msg, t)
            if extras:
                imu = Imu()
                imu.header.stamp = t
                imu.angular_velocity.x, imu.angular_velocity.y, imu.angular_velocity.z = 0.01 * k, 0.02, -0.03
                imu.linear_acceleration.z = 9.81
                bag.write("/imu/data", imu, t)
                odom = Odometry()
                odom.header.stamp = t
                odom.pose.pose.position.x = 1.5 * k
                odom.pose.pose.orientation.w = 1.0
                bag.write("/ground_truth/odom", odom, t)
                pose = PoseStamped()
                pose.header.stamp = t
                pose.pose.position.y = -2.0 * k
                pose.pose.orientation.z, pose.pose.orientation.w = 0.6, 0.8
                bag.write("/ground_truth/pose", pose, t)


def many_chunks(path, scans=40, points=200):
    """Small chunks so that damage stays local to a few messages."""
    with rosbag.Bag(path, "w", chunk_threshold=4096) as bag:
        for k in range(scans):
            msg = PointCloud2()
            msg.header.stamp = stamp(k)
            msg.header.frame_id = "radar"
            msg.height, msg.width = 1, points
            names = ["x", "y", "z", "range", "elevation", "azimuth", "power", "doppler"]
            msg.fields = [PointField(n, 4 * j, PointField.FLOAT32, 1) for j, n in enumerate(names)]
            msg.point_step, msg.row_step = 32, 32 * points
            msg.data = b"".join(struct.pack("<8f", *expected_point(k, i)) for i in range(points))
            bag.write("/hugin_raf_1/radar_data", msg, stamp(k))
            imu = Imu()
            imu.header.stamp = stamp(k)
            bag.write("/imu/data", imu, stamp(k))


def lying_clouds(path):
    """Scan 1: point_step smaller than the fields; scan 2: fewer bytes than width says; scan 3: all NaN."""
    with rosbag.Bag(path, "w") as bag:
        for k in range(5):
            msg = hugin_cloud(k)
            if k == 1:
                msg.point_step = 16
            elif k == 2:
                msg.width = N_POINTS + 5
                msg.row_step = 32 * msg.width
            elif k == 3:
                msg.data = struct.pack("<f", float("nan")) * (8 * N_POINTS)
            bag.write("/hugin_raf_1/radar_data", msg, stamp(k))


def main():
    out = sys.argv[1]
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "hugin.bag"), hugin_cloud)
    write(os.path.join(out, "bigendian.bag"), lambda k: hugin_cloud(k, True), extras=False)
    write(os.path.join(out, "float64.bag"), float64_cloud, topic="/radar/points", extras=False)
    write(os.path.join(out, "channels.bag"), channel_cloud, topic="/radar/cloud", extras=False)
    write(os.path.join(out, "faults.bag"), hugin_cloud, extras=False, nan_scan=2, backwards=True)
    many_chunks(os.path.join(out, "many_chunks.bag"))
    lying_clouds(os.path.join(out, "lies.bag"))
    data = open(os.path.join(out, "hugin.bag"), "rb").read()
    with open(os.path.join(out, "truncated.bag"), "wb") as f:
        f.write(data[: len(data) // 2])


if __name__ == "__main__":
    main()

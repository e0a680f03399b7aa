#!/usr/bin/python3
"""Writes rosbag2 recordings for the tests with rosbag2_writer.py (independent of dorado's reader).

  make_ros2_bags.py convert IN.bag OUT_DIR   the ROS1 bag (read with Debian's python3-rosbag) as
                                             OUT_DIR/data.db3, data.mcap (zstd), data_lz4.mcap and a
                                             folder data_split/ (metadata.yaml + two .mcap files)
  make_ros2_bags.py fixtures OUT_DIR         small recordings with known content and damaged ones
  make_ros2_bags.py big OUT.mcap MEGABYTES   a long recording for the memory and speed benchmark
Point i of scan k has the values of expected_point(k, i) (the formula of make_test_bags.py).
"""
import os
import shutil
import struct
import sys

import rosbag2_writer as w

N_POINTS = 12
N_SCANS = 5
T0 = 1690000000
RADAR = "/hugin_raf_1/radar_data"
NAMES = ["x", "y", "z", "range", "elevation", "azimuth", "power", "doppler"]
CLOUD2 = "sensor_msgs/msg/PointCloud2"


def expected_point(k, i):
    return (0.5 * i + k, -0.25 * i, 0.125 * i - 1.0, 2.0 + i, 0.01 * i, -0.02 * i, 10.0 + i, 0.1 * i - 0.5)


def stamp(k):
    return T0 + k // 10, (k % 10) * 100_000_000 + 123


def ns(sec, nanosec):
    return sec * 1_000_000_000 + nanosec


def hugin_cloud(k, n_points=N_POINTS, big_endian_cdr=False):
    fields = [(n, 4 * j, 7, 1) for j, n in enumerate(NAMES)]
    data = b"".join(struct.pack("<8f", *expected_point(k, i % N_POINTS)) for i in range(n_points))
    return w.pointcloud2(*stamp(k), "radar", 1, n_points, fields, False, 32, 32 * n_points, data,
                         big_endian_cdr=big_endian_cdr)


def known_messages():
    """(topic, type, log time, bytes): 5 scans, 20 IMU samples, 5 odometry poses, 5 poses."""
    out = []
    for k in range(N_SCANS):
        sec, nsec = stamp(k)
        t = ns(sec, nsec)
        out.append((RADAR, CLOUD2, t + 1000, hugin_cloud(k, big_endian_cdr=(k == 3))))
        out.append(("/odom", "nav_msgs/msg/Odometry", t + 2000,
                    w.odometry(sec, nsec, "map", "base", (k, 2.0 * k, -k), (0, 0, 0.6, 0.8))))
        out.append(("/pose", "geometry_msgs/msg/PoseStamped", t + 3000,
                    w.pose_stamped(sec, nsec, "map", (k, 1, 2), (0, 0, 0, 1))))
        for j in range(4):
            ti = t + 25_000_000 * j
            out.append(("/imu", "sensor_msgs/msg/Imu", ti + 500,
                        w.imu(ti // 1_000_000_000, ti % 1_000_000_000, "imu", (0, 0, 0, 1),
                              (0.1 * k, 0.01 * j, -0.5), (1.0, 2.0 * j, 9.81))))
    out.sort(key=lambda m: m[2])
    return out


def write(writer, messages):
    for topic, type_name, t, data in messages:
        writer.write(topic, type_name, t, data)
    writer.close()


def fixtures(out):
    os.makedirs(out, exist_ok=True)
    msgs = known_messages()
    write(w.Db3Writer(out + "/known.db3"), msgs)
    for comp, name in (("zstd", "known.mcap"), ("lz4", "known_lz4.mcap"), ("", "known_raw.mcap")):
        write(w.McapWriter(out + "/" + name, compression=comp, chunk_size=2000), msgs)
    write(w.McapWriter(out + "/nosummary.mcap", summary=False, chunk_size=2000), msgs)
    write(w.McapWriter(out + "/unchunked.mcap", chunked=False), msgs)
    # A folder with two files: scans 0-2 in the first, 3-4 in the second.
    split = out + "/split"
    shutil.rmtree(split, ignore_errors=True)
    os.makedirs(split)
    cut = ns(*stamp(3))
    write(w.McapWriter(split + "/split_0.mcap"), [m for m in msgs if m[2] < cut])
    write(w.McapWriter(split + "/split_1.mcap"), [m for m in msgs if m[2] >= cut])
    w.write_metadata(split, ["split_0.mcap", "split_1.mcap"], "mcap", {})
    faults(out, msgs)


def faults(out, msgs):
    """Each damaged recording keeps the scans a reader can still trust."""
    radar_only = [m for m in msgs if m[0] == RADAR]
    # Unstored-and-checksummed chunks of one scan each; the third scan's chunk gets a flipped byte.
    writer = w.McapWriter(out + "/crc.mcap", compression="", chunk_size=1)
    write(writer, radar_only)
    data = bytearray(open(out + "/crc.mcap", "rb").read())
    # opcode, length, start, end, uncompressed size, crc, compression "", records length: 49 bytes
    flip = writer.chunk_offsets[2] + 49 + 200  # inside the third chunk's point data
    data[flip] ^= 0xFF
    open(out + "/crc.mcap", "wb").write(bytes(data))
    # The second chunk names a compression dorado does not read.
    writer = w.McapWriter(out + "/bz2.mcap", compression="zstd", chunk_size=1 << 30)
    for i, (topic, type_name, t, d) in enumerate(radar_only):
        writer.write(topic, type_name, t, d)
        writer.flush(compression="bz2" if i == 1 else None)
    writer.close()
    # Cut-off files: the first scans are whole, the rest is missing.
    for name in ("known.mcap", "known.db3"):
        src = open(out + "/" + name, "rb").read()
        keep = len(src) * 6 // 10 if name.endswith(".mcap") else len(src) - 8192  # 2 pages
        open(out + "/truncated_" + name.replace("known.", "") + "." + name.split(".")[1], "wb") \
            .write(src[:keep])
    # A radar topic of a type dorado cannot read.
    db = w.Db3Writer(out + "/laserscan.db3")
    db.write(RADAR, "sensor_msgs/msg/LaserScan", 1, b"\x00\x01\x00\x00")
    db.close()
    # A rosbag2 folder whose metadata.yaml is missing.
    nometa = out + "/nometa"
    shutil.rmtree(nometa, ignore_errors=True)
    os.makedirs(nometa)
    shutil.copy(out + "/known.db3", nometa + "/nometa_0.db3")


def ros1_to_cdr(type_name, m):
    """The ROS 2 serialization of a ROS1 message (same fields, ROS 2 type name)."""
    h = m.header
    if type_name == "sensor_msgs/PointCloud2":
        fields = [(f.name, f.offset, f.datatype, f.count) for f in m.fields]
        return w.pointcloud2(h.stamp.secs, h.stamp.nsecs, h.frame_id, m.height, m.width, fields,
                             m.is_bigendian, m.point_step, m.row_step, m.data, m.is_dense)
    if type_name == "sensor_msgs/Imu":
        o, a, l = m.orientation, m.angular_velocity, m.linear_acceleration
        return w.imu(h.stamp.secs, h.stamp.nsecs, h.frame_id, (o.x, o.y, o.z, o.w),
                     (a.x, a.y, a.z), (l.x, l.y, l.z))
    pose = m.pose.pose if type_name == "nav_msgs/Odometry" else m.pose
    p, q = pose.position, pose.orientation
    if type_name == "nav_msgs/Odometry":
        return w.odometry(h.stamp.secs, h.stamp.nsecs, h.frame_id, m.child_frame_id,
                          (p.x, p.y, p.z), (q.x, q.y, q.z, q.w))
    return w.pose_stamped(h.stamp.secs, h.stamp.nsecs, h.frame_id, (p.x, p.y, p.z),
                          (q.x, q.y, q.z, q.w))


def ros1_messages(path):
    import rosbag
    with rosbag.Bag(path) as bag:
        types = {c.topic: c.datatype for c in bag._get_connections()}
        for topic, msg, t in bag.read_messages():
            ros1 = types[topic]
            yield topic, ros1.replace("/", "/msg/"), t.to_nsec(), ros1_to_cdr(ros1, msg)


def convert(bag, out):
    os.makedirs(out, exist_ok=True)
    msgs = list(ros1_messages(bag))
    write(w.Db3Writer(out + "/data.db3"), msgs)
    write(w.McapWriter(out + "/data.mcap", compression="zstd"), msgs)
    write(w.McapWriter(out + "/data_lz4.mcap", compression="lz4"), msgs)
    split = out + "/data_split"
    shutil.rmtree(split, ignore_errors=True)
    os.makedirs(split)
    half = msgs[len(msgs) // 2][2]
    write(w.McapWriter(split + "/data_split_0.mcap"), [m for m in msgs if m[2] < half])
    write(w.McapWriter(split + "/data_split_1.mcap"), [m for m in msgs if m[2] >= half])
    w.write_metadata(split, ["data_split_0.mcap", "data_split_1.mcap"], "mcap", {})


def big(path, megabytes):
    """Scans of 4000 random points (128 kB, 50 distinct ones in turn, so that zstd cannot shrink
    them) at 10 Hz and IMU at 200 Hz until the messages hold the size."""
    import array
    import random
    random.seed(1)
    clouds = []
    for _ in range(50):
        values = array.array("f", [random.uniform(-50.0, 50.0) for _ in range(4000 * 8)])
        clouds.append(values.tobytes())
    fields = [(n, 4 * j, 7, 1) for j, n in enumerate(NAMES)]
    writer = w.McapWriter(path, compression="zstd") if path.endswith(".mcap") else w.Db3Writer(path)
    k = 0
    written = 0
    while written < megabytes * 1_000_000:
        sec, nsec = stamp(k)
        t = ns(sec, nsec)
        cloud = w.pointcloud2(sec, nsec, "radar", 1, 4000, fields, False, 32, 32 * 4000, clouds[k % 50])
        writer.write(RADAR, CLOUD2, t, cloud)
        for j in range(20):
            ti = t + 5_000_000 * j + 1
            imu = w.imu(ti // 1_000_000_000, ti % 1_000_000_000, "imu", (0, 0, 0, 1), (0.0, 0.0, 0.1),
                        (0.0, 0.0, 9.81))
            writer.write("/imu", "sensor_msgs/msg/Imu", ti, imu)
            written += len(imu)
        written += len(cloud)
        k += 1
    writer.close()
    print("wrote %s: %d scans" % (path, k))


if __name__ == "__main__":
    if sys.argv[1] == "convert":
        convert(sys.argv[2], sys.argv[3])
    elif sys.argv[1] == "fixtures":
        fixtures(sys.argv[2])
    elif sys.argv[1] == "big":
        big(sys.argv[2], int(sys.argv[3]))
    else:
        sys.exit(__doc__)

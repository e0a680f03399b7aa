#!/usr/bin/python3
"""A rosbag2 writer for tests, independent of dorado's reader: CDR (XCDR1, the ROS 2 "cdr" format),
the rosbag2 sqlite3 schema and MCAP records, each encoded here from its public specification
(OMG CDR alignment rules; rosbag2_storage_sqlite3's tables; https://mcap.dev/spec).
Only the Python standard library (sqlite3, struct, zlib.crc32) plus Debian's python3-zstandard and
python3-lz4 for compressed MCAP chunks.
"""
import os
import sqlite3
import struct
import zlib


class Cdr:
    """Serializes primitives with CDR alignment (relative to the end of the 4-byte encapsulation)."""

    def __init__(self, big_endian=False):
        self.big = big_endian
        self.e = ">" if big_endian else "<"
        self.b = bytearray()

    def _put(self, fmt, size, *v):
        self.b += b"\0" * ((-len(self.b)) % size)
        self.b += struct.pack(self.e + fmt, *v)

    def u8(self, v): self._put("B", 1, v)
    def boolean(self, v): self.u8(1 if v else 0)
    def i32(self, v): self._put("i", 4, v)
    def u32(self, v): self._put("I", 4, v)
    def f64(self, *v):
        for x in v:
            self._put("d", 8, x)

    def string(self, s):
        raw = s.encode()
        self.u32(len(raw) + 1)
        self.b += raw + b"\0"

    def octets(self, data):
        self.u32(len(data))
        self.b += bytes(data)

    def bytes(self):
        return (b"\x00\x00" if self.big else b"\x00\x01") + b"\x00\x00" + bytes(self.b)


def header(c, sec, nanosec, frame_id):
    c.i32(sec)
    c.u32(nanosec)
    c.string(frame_id)


def pointcloud2(sec, nanosec, frame_id, height, width, fields, is_bigendian, point_step, row_step,
                data, is_dense=True, big_endian_cdr=False):
    """fields: (name, offset, datatype, count) tuples."""
    c = Cdr(big_endian_cdr)
    header(c, sec, nanosec, frame_id)
    c.u32(height)
    c.u32(width)
    c.u32(len(fields))
    for name, offset, datatype, count in fields:
        c.string(name)
        c.u32(offset)
        c.u8(datatype)
        c.u32(count)
    c.boolean(is_bigendian)
    c.u32(point_step)
    c.u32(row_step)
    c.octets(data)
    c.boolean(is_dense)
    return c.bytes()


def imu(sec, nanosec, frame_id, orientation_xyzw, omega, accel):
    c = Cdr()
    header(c, sec, nanosec, frame_id)
    c.f64(*orientation_xyzw)
    c.f64(*([0.0] * 9))
    c.f64(*omega)
    c.f64(*([0.0] * 9))
    c.f64(*accel)
    c.f64(*([0.0] * 9))
    return c.bytes()


def _pose(c, position, orientation_xyzw):
    c.f64(*position)
    c.f64(*orientation_xyzw)


def odometry(sec, nanosec, frame_id, child_frame_id, position, orientation_xyzw):
    c = Cdr()
    header(c, sec, nanosec, frame_id)
    c.string(child_frame_id)
    _pose(c, position, orientation_xyzw)
    c.f64(*([0.0] * 36))
    c.f64(*([0.0] * 6))  # twist.twist
    c.f64(*([0.0] * 36))
    return c.bytes()


def pose_stamped(sec, nanosec, frame_id, position, orientation_xyzw):
    c = Cdr()
    header(c, sec, nanosec, frame_id)
    _pose(c, position, orientation_xyzw)
    return c.bytes()


class Db3Writer:
    """rosbag2_storage_sqlite3's layout (Humble): topics and messages, with timestamp_idx."""

    def __init__(self, path, page_size=4096):
        if os.path.exists(path):
            os.remove(path)
        self.db = sqlite3.connect(path)
        self.db.execute("PRAGMA page_size=%d" % page_size)
        self.db.executescript(
            "CREATE TABLE schema(schema_version INTEGER PRIMARY KEY, ros_distro TEXT NOT NULL);"
            "INSERT INTO schema VALUES (3, 'humble');"
            "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL,"
            " serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL);"
            "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL,"
            " timestamp INTEGER NOT NULL, data BLOB NOT NULL);"
            "CREATE INDEX timestamp_idx ON messages (timestamp ASC);")
        self.ids = {}

    def write(self, topic, type_name, log_time_ns, data):
        if topic not in self.ids:
            self.ids[topic] = len(self.ids) + 1
            self.db.execute("INSERT INTO topics VALUES (?, ?, ?, 'cdr', '')",
                            (self.ids[topic], topic, type_name))
        self.db.execute("INSERT INTO messages (topic_id, timestamp, data) VALUES (?, ?, ?)",
                        (self.ids[topic], log_time_ns, data))

    def close(self):
        self.db.commit()
        self.db.close()


MAGIC = b"\x89MCAP0\r\n"


def _s(text):
    raw = text.encode()
    return struct.pack("<I", len(raw)) + raw


def _record(op, body):
    return struct.pack("<BQ", op, len(body)) + body


def compress(kind, raw):
    if kind == "":
        return raw
    if kind == "zstd":
        import zstandard
        return zstandard.ZstdCompressor().compress(raw)
    if kind == "lz4":
        import lz4.frame
        return lz4.frame.compress(raw)
    return raw  # an unsupported name: the bytes are stored as they are


class McapWriter:
    """MCAP with Schema/Channel records before the chunks and again in the summary section."""

    def __init__(self, path, compression="zstd", chunk_size=1 << 20, summary=True, chunked=True):
        self.f = open(path, "wb")
        self.compression = compression
        self.chunk_size = chunk_size
        self.summary = summary
        self.chunked = chunked
        self.channels = {}
        self.definitions = b""
        self.chunk = bytearray()
        self.times = []
        self.chunk_offsets = []
        self.f.write(MAGIC + _record(0x01, _s("ros2") + _s("dorado-test-writer")))

    def write(self, topic, type_name, log_time_ns, data, sequence=0):
        if topic not in self.channels:
            cid = len(self.channels) + 1
            self.channels[topic] = cid
            schema = _record(0x03, struct.pack("<H", cid) + _s(type_name) + _s("ros2msg") +
                             struct.pack("<I", 0))
            channel = _record(0x04, struct.pack("<HH", cid, cid) + _s(topic) + _s("cdr") +
                              struct.pack("<I", 0))
            self.definitions += schema + channel
            self.f.write(schema + channel)
        body = struct.pack("<HIQQ", self.channels[topic], sequence, log_time_ns, log_time_ns) + data
        if not self.chunked:  # a Message record in the data section itself
            self.f.write(_record(0x05, body))
            return
        self.chunk += _record(0x05, body)
        self.times.append(log_time_ns)
        if len(self.chunk) >= self.chunk_size:
            self.flush()

    def flush(self, compression=None):
        if not self.chunk:
            return
        kind = self.compression if compression is None else compression
        raw = bytes(self.chunk)
        packed = compress(kind, raw)
        body = (struct.pack("<QQQI", min(self.times), max(self.times), len(raw), zlib.crc32(raw)) +
                _s(kind) + struct.pack("<Q", len(packed)) + packed)
        self.chunk_offsets.append(self.f.tell())
        self.f.write(_record(0x06, body))
        self.chunk = bytearray()
        self.times = []

    def close(self):
        self.flush()
        self.f.write(_record(0x0F, struct.pack("<I", 0)))
        summary_start = 0
        if self.summary:
            summary_start = self.f.tell()
            self.f.write(self.definitions)
        self.f.write(_record(0x02, struct.pack("<QQI", summary_start, 0, 0)) + MAGIC)
        self.f.close()


def write_metadata(folder, files, storage, topics):
    """metadata.yaml of a rosbag2 folder; topics: {name: (type, count)}."""
    lines = ["rosbag2_bagfile_information:", "  version: 5", "  storage_identifier: " + storage,
             "  relative_file_paths:"]
    lines += ["    - " + f for f in files]
    lines += ["  topics_with_message_count:"]
    for name, (type_name, count) in sorted(topics.items()):
        lines += ["    - topic_metadata:", "        name: " + name, "        type: " + type_name,
                  "        serialization_format: cdr", '        offered_qos_profiles: ""',
                  "      message_count: %d" % count]
    with open(folder + "/metadata.yaml", "w") as f:
        f.write("\n".join(lines) + "\n")

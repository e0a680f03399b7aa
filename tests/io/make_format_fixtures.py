#!/usr/bin/python3
"""Writes small RadarScenes and nuScenes files in those data sets' own schemas, for test_format_readers.

usage: make_format_fixtures.py SHARED_REAL_DIR OUT_DIR [SCANS]

The scans come from the shared folders' first SCANS scans (../shared/data/real: float32 rows
x, y, z, rcs, v_r, label in the radar frame, times.txt) when they are there, else synthetic ones.
What was written is also left as OUT_DIR/<set>/expected/{scans/NNNNN.bin, times.txt} (times in
seconds after TIME_OFFSET_US), so the test compares the reader with the values put in, never with
the reader.

Schemas as the devkits read them (oleschum/radar_scenes, nutonomy/nuscenes-devkit):
- RadarScenes: radar_data.h5 with compound tables radar_data (timestamp, sensor_id, range_sc,
  azimuth_sc, rcs, vr, vr_compensated, x_cc, y_cc, x_seq, y_seq, uuid, track_id, label_id) and
  odometry (timestamp, x_seq, y_seq, yaw_seq, vx, yaw_rate), timestamps in microseconds;
  scenes.json (scenes keyed by timestamp: sensor_id, radar_indices [first, end), ...);
  sensors.json (radar_<id>: x, y, yaw) next to the sequence folders.
- nuScenes: binary PCD v0.7 sweeps with the 18 ARS408 fields (43 bytes a point) and the JSON tables
  scene, sample, sample_data, sensor, calibrated_sensor, ego_pose (rotations w x y z).
Malformed variants sit next to them (see the test).
"""
import json
import math
import os
import shutil
import sys

import h5py
import numpy as np

TIME_OFFSET_US = 1_533_151_603_000_000  # a nuScenes-like epoch time: int64 microseconds
SENSOR_ID = 3
MOUNTS = {  # RadarScenes' sensors.json (its devkit's defaults)
    1: (3.663, -0.873, -1.48418552),
    2: (3.86, -0.70, -0.436185662),
    3: (3.86, 0.70, 0.436),
    4: (3.663, 0.873, 1.484),
}
RADAR_DTYPE = np.dtype([
    ("timestamp", "<u8"), ("sensor_id", "u1"), ("range_sc", "<f4"), ("azimuth_sc", "<f4"),
    ("rcs", "<f4"), ("vr", "<f4"), ("vr_compensated", "<f4"), ("x_cc", "<f4"), ("y_cc", "<f4"),
    ("x_seq", "<f4"), ("y_seq", "<f4"), ("uuid", "S32"), ("track_id", "S32"), ("label_id", "u1")])
ODOMETRY_DTYPE = np.dtype([
    ("timestamp", "<u8"), ("x_seq", "<f4"), ("y_seq", "<f4"), ("yaw_seq", "<f4"), ("vx", "<f4"),
    ("yaw_rate", "<f4")])
PCD_FIELDS = ["x", "y", "z", "dyn_prop", "id", "rcs", "vx", "vy", "vx_comp", "vy_comp",
              "is_quality_valid", "ambig_state", "x_rms", "y_rms", "invalid_state", "pdh0",
              "vx_rms", "vy_rms"]
PCD_SIZES = [4, 4, 4, 1, 2, 4, 4, 4, 4, 4, 1, 1, 1, 1, 1, 1, 1, 1]
PCD_TYPES = ["F", "F", "F", "I", "I", "F", "F", "F", "F", "F", "I", "I", "I", "I", "I", "I", "I", "I"]


def pcd_dtype(types=PCD_TYPES, sizes=PCD_SIZES, fields=PCD_FIELDS):
    code = {("F", 4): "<f4", ("F", 8): "<f8", ("I", 1): "i1", ("I", 2): "<i2", ("I", 4): "<i4"}
    return np.dtype([(f, code[(t, s)]) for f, t, s in zip(fields, types, sizes)])


def load_scans(folder, count, rng):
    """(times [s], [rows (n, 6) float32]) from a shared folder, or synthetic ones."""
    if folder and os.path.isdir(folder):
        names = sorted(f for f in os.listdir(os.path.join(folder, "scans")) if f.endswith(".bin"))
        times = np.loadtxt(os.path.join(folder, "times.txt"))[:count]
        scans = [np.fromfile(os.path.join(folder, "scans", n), dtype="<f4").reshape(-1, 6)
                 for n in names[:count]]
        return list(times), scans, True
    times, scans = [], []
    for k in range(count):
        n = int(rng.integers(60, 130))
        xy = np.stack([rng.uniform(2, 60, n), rng.uniform(-30, 30, n)], axis=1)
        v = -12.0 * xy[:, 0] / np.hypot(xy[:, 0], xy[:, 1])
        rows = np.zeros((n, 6), "<f4")
        rows[:, 0:2], rows[:, 3], rows[:, 4] = xy, rng.uniform(-20, 20, n), v
        rows[:, 5] = rng.choice([0, 1, 11], n)
        times.append(0.0646 + 0.0756 * k)
        scans.append(rows)
    return times, scans, False


def write_expected(out, times, scans):
    os.makedirs(os.path.join(out, "expected", "scans"), exist_ok=True)
    with open(os.path.join(out, "expected", "times.txt"), "w") as f:
        for k, (t, rows) in enumerate(zip(times, scans)):
            f.write("%.6f\n" % t)
            rows.astype("<f4").tofile(os.path.join(out, "expected", "scans", "%05d.bin" % k))


def stamp_us(t):
    return TIME_OFFSET_US + int(round(t * 1e6))


def radarscenes(shared, out, count, rng):
    times, scans, real = load_scans(os.path.join(shared, "radarscenes_105_radar3"), count, rng)
    reference = None
    if real:
        reference = np.loadtxt(os.path.join(shared, "radarscenes_105_radar3", "reference.tum"))
    seq = os.path.join(out, "sequence_105")
    os.makedirs(seq, exist_ok=True)
    write_expected(out, times, scans)
    rows, scenes = [], {}
    # Scenes of sensor 3 interleaved with scenes of sensor 1 (other points, in between in time).
    events = [(stamp_us(t), SENSOR_ID, s) for t, s in zip(times, scans)]
    for t, s in zip(times, scans):
        other = s[: max(1, len(s) // 3)].copy()
        other[:, 0] += 1.0
        events.append((stamp_us(t) + 20_000, 1, other))
    events.sort(key=lambda e: e[0])
    first = 0
    for ts, sensor, s in events:
        r = np.zeros(len(s), RADAR_DTYPE)
        r["timestamp"], r["sensor_id"] = ts, sensor
        r["range_sc"] = np.hypot(s[:, 0], s[:, 1])
        r["azimuth_sc"] = np.arctan2(s[:, 1], s[:, 0])
        r["rcs"], r["vr"], r["label_id"] = s[:, 3], s[:, 4], s[:, 5]
        mx, my, myaw = MOUNTS[sensor]
        r["x_cc"] = mx + math.cos(myaw) * s[:, 0] - math.sin(myaw) * s[:, 1]
        r["y_cc"] = my + math.sin(myaw) * s[:, 0] + math.cos(myaw) * s[:, 1]
        r["uuid"] = [("%032x" % int(rng.integers(0, 2**62))).encode() for _ in range(len(s))]
        r["track_id"] = b""
        rows.append(r)
        scenes[str(ts)] = {"sensor_id": int(sensor), "radar_indices": [first, first + len(s)],
                           "odometry_timestamp": int(ts), "odometry_index": 0,
                           "image_name": "%d.jpg" % ts}
        first += len(s)
    keys = sorted(scenes, key=int)
    for i, k in enumerate(keys):
        scenes[k]["prev_timestamp"] = int(keys[i - 1]) if i > 0 else None
        scenes[k]["next_timestamp"] = int(keys[i + 1]) if i + 1 < len(keys) else None
    radar_data = np.concatenate(rows)
    # The car's odometry at the scans' times (the reference when the shared set is there).
    odo = np.zeros(len(times), ODOMETRY_DTYPE)
    odo["timestamp"] = [stamp_us(t) for t in times]
    if reference is not None:
        odo["x_seq"], odo["y_seq"] = reference[: len(times), 1], reference[: len(times), 2]
        odo["yaw_seq"] = 2 * np.arctan2(reference[: len(times), 6], reference[: len(times), 7])
    else:
        odo["x_seq"] = 12.0 * np.asarray(times)
        odo["yaw_seq"] = 0.05 * np.asarray(times)
    with h5py.File(os.path.join(seq, "radar_data.h5"), "w") as f:
        f.create_dataset("radar_data", data=radar_data)
        f.create_dataset("odometry", data=odo)
    with open(os.path.join(seq, "scenes.json"), "w") as f:
        json.dump({"sequence_name": "sequence_105", "category": "train",
                   "first_timestamp": int(keys[0]), "last_timestamp": int(keys[-1]),
                   "scenes": scenes}, f)
    with open(os.path.join(out, "sensors.json"), "w") as f:
        json.dump({"radar_%d" % i: {"id": i, "x": m[0], "y": m[1], "yaw": m[2]}
                   for i, m in MOUNTS.items()}, f)
    np.savetxt(os.path.join(out, "expected", "odometry.txt"),
               np.stack([odo["timestamp"] - TIME_OFFSET_US, odo["x_seq"], odo["y_seq"],
                         odo["yaw_seq"]], axis=1), fmt="%.9g")

    def variant(name, mutate):
        d = os.path.join(out, name)
        os.makedirs(d, exist_ok=True)
        shutil.copy(os.path.join(seq, "scenes.json"), d)
        with h5py.File(os.path.join(d, "radar_data.h5"), "w") as f:
            mutate(f, radar_data, odo)

    variant("missing_dataset", lambda f, r, o: f.create_dataset("odometry", data=o))
    wrong = np.dtype([(n, "<i4" if n == "vr" else RADAR_DTYPE[n]) for n in RADAR_DTYPE.names])
    variant("wrong_dtype", lambda f, r, o: (f.create_dataset("radar_data", data=r.astype(wrong)),
                                            f.create_dataset("odometry", data=o)))
    no_vr = [n for n in RADAR_DTYPE.names if n != "vr"]
    variant("missing_field", lambda f, r, o: (f.create_dataset("radar_data", data=r[no_vr]),
                                              f.create_dataset("odometry", data=o)))
    d = os.path.join(out, "truncated")
    os.makedirs(d, exist_ok=True)
    shutil.copy(os.path.join(seq, "scenes.json"), d)
    data = open(os.path.join(seq, "radar_data.h5"), "rb").read()
    open(os.path.join(d, "radar_data.h5"), "wb").write(data[: len(data) // 2])
    return real


def write_pcd(path, records, types=PCD_TYPES, sizes=PCD_SIZES, fields=PCD_FIELDS, truncate=0):
    header = ("# .PCD v0.7 - Point Cloud Data file format\nVERSION 0.7\nFIELDS %s\nSIZE %s\n"
              "TYPE %s\nCOUNT %s\nWIDTH %d\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS %d\n"
              "DATA binary\n" % (" ".join(fields), " ".join(map(str, sizes)), " ".join(types),
                                 " ".join("1" * len(fields)), len(records), len(records)))
    body = records.tobytes()
    with open(path, "wb") as f:
        f.write(header.encode() + body[: len(body) - truncate])


def sweep_records(rows, rng):
    """The ARS408 clusters of one scan: vx, vy whose line-of-sight part is v_r, plus a random
    tangential part the Doppler must not see."""
    n = len(rows)
    r = np.zeros(n, pcd_dtype())
    x, y = rows[:, 0].astype(np.float64), rows[:, 1].astype(np.float64)
    d = np.hypot(x, y)
    tangential = rng.uniform(-3, 3, n)
    r["x"], r["y"], r["z"] = rows[:, 0], rows[:, 1], rows[:, 2]
    r["vx"] = rows[:, 4] * x / d - tangential * y / d
    r["vy"] = rows[:, 4] * y / d + tangential * x / d
    r["vx_comp"], r["vy_comp"] = rng.uniform(-1, 1, n), rng.uniform(-1, 1, n)
    r["rcs"], r["dyn_prop"] = rows[:, 3], rows[:, 5]
    r["id"] = np.arange(n)
    r["ambig_state"], r["invalid_state"] = 3, 0
    r["is_quality_valid"] = 1
    return r


def nuscenes(shared, out, count, rng):
    base = os.path.join(shared, "nuscenes_scene-0061")
    times, scans, real = load_scans(os.path.join(base, "radar_front"), count, rng)
    write_expected(out, times, scans)
    mount = (3.412, 0.0, 0.5, 0.0, 0.0, 0.001745328366, 0.999998476913)  # mounts.txt front
    gt = None
    if real:
        gt = np.loadtxt(os.path.join(base, "ground_truth.tum"))
        for line in open(os.path.join(base, "mounts.txt")):
            if line.startswith("front "):
                mount = tuple(float(v) for v in line.split()[1:])
    tables = {k: [] for k in ["scene", "sample", "sample_data", "sensor", "calibrated_sensor",
                              "ego_pose", "log"]}
    tables["log"].append({"token": "log0", "logfile": "n015", "vehicle": "n015",
                          "date_captured": "2018-07-24", "location": "singapore-onenorth"})
    for ch in ["RADAR_FRONT", "RADAR_BACK_LEFT", "LIDAR_TOP"]:
        tables["sensor"].append({"token": "sensor_" + ch, "channel": ch,
                                 "modality": "lidar" if ch == "LIDAR_TOP" else "radar"})
        tables["calibrated_sensor"].append({
            "token": "cs_" + ch, "sensor_token": "sensor_" + ch,
            "translation": list(mount[:3]) if ch == "RADAR_FRONT" else [0.0, 0.0, 1.8],
            "rotation": [mount[6], mount[3], mount[4], mount[5]] if ch == "RADAR_FRONT"
            else [1.0, 0.0, 0.0, 0.0], "camera_intrinsic": []})
    # Two scenes: the first holds the scans, the second one more sweep that must not be read.
    samples = []
    for s, scene in enumerate(["scene-0061", "scene-0103"]):
        tables["scene"].append({"token": "scene%d" % s, "name": scene, "log_token": "log0",
                                "description": "", "nbr_samples": 0,
                                "first_sample_token": "", "last_sample_token": ""})
    span = times[-1] + 0.5
    for k in range(int(span / 0.5) + 1):
        samples.append({"token": "sample%d" % k, "timestamp": stamp_us(0.5 * k),
                        "scene_token": "scene0", "prev": "", "next": "", "data": {}, "anns": []})
    samples.append({"token": "sample_other", "timestamp": stamp_us(span + 30), "scene_token":
                    "scene1", "prev": "", "next": "", "data": {}, "anns": []})
    tables["sample"] = samples
    pose_at = {}

    def add_data(token, channel, t_us, filename, sample, pose):
        tables["ego_pose"].append({"token": "ego_" + token, "timestamp": t_us,
                                   "translation": pose[:3], "rotation": pose[3:]})
        pose_at[t_us] = pose
        tables["sample_data"].append({
            "token": token, "sample_token": sample, "ego_pose_token": "ego_" + token,
            "calibrated_sensor_token": "cs_" + channel, "timestamp": t_us, "fileformat": "pcd",
            "is_key_frame": False, "height": 0, "width": 0, "filename": filename, "prev": "",
            "next": ""})

    def pose_of(t):
        if gt is None:
            return [12.0 * t, 0.0, 0.0, math.cos(0.025 * t), 0.0, 0.0, math.sin(0.025 * t)]
        row = gt[int(np.argmin(np.abs(gt[:, 0] - t)))]
        return [row[1], row[2], row[3], row[7], row[4], row[5], row[6]]  # w x y z

    def sample_of(t):
        return "sample%d" % min(int(round(t / 0.5)), len(samples) - 2)

    os.makedirs(os.path.join(out, "sweeps", "RADAR_FRONT"), exist_ok=True)
    os.makedirs(os.path.join(out, "sweeps", "RADAR_BACK_LEFT"), exist_ok=True)
    for k, (t, rows) in enumerate(zip(times, scans)):
        name = "sweeps/RADAR_FRONT/front_%05d.pcd" % k
        write_pcd(os.path.join(out, name), sweep_records(rows, rng))
        add_data("front%d" % k, "RADAR_FRONT", stamp_us(t), name, sample_of(t), pose_of(t))
    # The ego pose ~50 Hz: LIDAR_TOP sample_data carrying the reference's poses.
    if gt is not None:
        for i, row in enumerate(gt[gt[:, 0] <= times[-1]]):
            add_data("lidar%d" % i, "LIDAR_TOP", stamp_us(row[0]), "samples/LIDAR_TOP/%d.bin" % i,
                     sample_of(row[0]), pose_of(row[0]))
    extra = "sweeps/RADAR_FRONT/other_scene.pcd"
    write_pcd(os.path.join(out, extra), sweep_records(scans[0], rng))
    add_data("front_other", "RADAR_FRONT", stamp_us(span + 30), extra, "sample_other",
             pose_of(0))
    # RADAR_BACK_LEFT: one good sweep, then a truncated one, vx as int16, vy missing.
    good = sweep_records(scans[0], rng)
    bad = [("good", {}), ("truncated", {"truncate": 7})]
    wrong_types = list(PCD_TYPES)
    wrong_sizes = list(PCD_SIZES)
    wrong_types[6], wrong_sizes[6] = "I", 2
    for k, (name, kw) in enumerate(bad):
        path = "sweeps/RADAR_BACK_LEFT/%s.pcd" % name
        write_pcd(os.path.join(out, path), good, **kw)
        add_data("back%d" % k, "RADAR_BACK_LEFT", stamp_us(times[k]), path, sample_of(times[k]),
                 pose_of(times[k]))
    wrong = good.astype(pcd_dtype(wrong_types, wrong_sizes))
    path = "sweeps/RADAR_BACK_LEFT/vx_int16.pcd"
    write_pcd(os.path.join(out, path), wrong, types=wrong_types, sizes=wrong_sizes)
    add_data("back2", "RADAR_BACK_LEFT", stamp_us(times[2]), path, sample_of(times[2]),
             pose_of(times[2]))
    no_vy = [f for f in PCD_FIELDS if f != "vy"]
    path = "sweeps/RADAR_BACK_LEFT/no_vy.pcd"
    write_pcd(os.path.join(out, path), good[no_vy].copy(),
              types=[t for f, t in zip(PCD_FIELDS, PCD_TYPES) if f != "vy"],
              sizes=[s for f, s in zip(PCD_FIELDS, PCD_SIZES) if f != "vy"], fields=no_vy)
    add_data("back3", "RADAR_BACK_LEFT", stamp_us(times[3]), path, sample_of(times[3]),
             pose_of(times[3]))
    # A header whose points * 43 bytes wraps round 64 bits to a few bytes.
    path = "sweeps/RADAR_BACK_LEFT/huge_points.pcd"
    write_pcd(os.path.join(out, path), good)
    data = open(os.path.join(out, path), "rb").read()
    claimed = b"%d" % (2**64 // 43 + 1)
    data = data.replace(b"WIDTH %d\n" % len(good), b"WIDTH " + claimed + b"\n", 1)
    data = data.replace(b"POINTS %d\n" % len(good), b"POINTS " + claimed + b"\n", 1)
    open(os.path.join(out, path), "wb").write(data)
    add_data("back4", "RADAR_BACK_LEFT", stamp_us(times[4]), path, sample_of(times[4]),
             pose_of(times[4]))
    os.makedirs(os.path.join(out, "v1.0-mini"), exist_ok=True)
    for name, records in tables.items():
        with open(os.path.join(out, "v1.0-mini", name + ".json"), "w") as f:
            json.dump(records, f, indent=0)
    # The scene's ego poses as put in (t [s after the offset], x y z, qw qx qy qz).
    with open(os.path.join(out, "expected", "ego_poses.txt"), "w") as f:
        for t_us in sorted(pose_at):
            if t_us < stamp_us(span):
                f.write("%.6f %s\n" % ((t_us - TIME_OFFSET_US) * 1e-6,
                                       " ".join("%.9f" % v for v in pose_at[t_us])))
    return real


def main():
    shared, out = sys.argv[1], sys.argv[2]
    count = int(sys.argv[3]) if len(sys.argv) > 3 else 20
    rng = np.random.default_rng(32)
    if os.path.exists(out):
        shutil.rmtree(out)
    real_rs = radarscenes(shared, os.path.join(out, "radarscenes"), count, rng)
    real_nu = nuscenes(shared, os.path.join(out, "nuscenes"), count, rng)
    print("radarscenes from %s, nuscenes from %s" % ("the shared set" if real_rs else "synthetic",
                                                    "the shared set" if real_nu else "synthetic"))


if __name__ == "__main__":
    main()

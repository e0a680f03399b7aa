#!/usr/bin/python3
"""Copies of the shared real drives in the devkits' own layouts, every radar, for the native readers.

usage: make_devkit_copies.py SHARED_REAL_DIR OUT_DIR

From ../shared/data/real (float32 scans x, y, z, rcs, v_r, label per radar, times.txt, the
reference, nuScenes' mounts.txt and CAN bus IMU; its README says how they were extracted) writes:
- OUT/nuscenes: v1.0-mini/{scene,sample,sample_data,sensor,calibrated_sensor,ego_pose,log}.json,
  sweeps/RADAR_*/*.pcd (binary PCD v0.7, the ARS408's 18 fields; vx, vy along the line of sight so
  that (x vx + y vy) / hypot(x, y) is the extract's v_r), can_bus/scene-0061_ms_imu.json. Scene
  scene-0061 holds the whole drive, five radars; scene-0103 the first 40 sweeps of RADAR_FRONT again,
  1000 s later. The ego poses: ground_truth.tum's, carried by LIDAR_TOP sample_data, and each sweep's
  interpolated at its time.
- OUT/RadarScenes/data: sensors.json (x, y, yaw of radar_1..4 as the README gives them),
  sequence_105/{radar_data.h5, scenes.json} with the four radars' scans (range_sc = hypot(x, y),
  azimuth_sc = atan2(y, x), float64) and the car's odometry (the four references' poses), sequence_106 the first
  100 scenes of it again.
- malformed copies beside them: nuscenes/v1.0-nocal (calibrated_sensor.json without RADAR_BACK_LEFT's
  record), nuscenes/v1.0-nopcd (one RADAR_FRONT sweep's file named but absent),
  nuscenes/v1.0-twocal (some RADAR_FRONT sweeps under a second calibration record),
  RadarScenes/data/sequence_107 (scenes.json without radar_data.h5);
- OUT/*.yaml: the native descriptions and descriptions of the same radars read from the extract
  folders (reader folder, a radars: list in the native readers' order, the same mounts).
Timestamps are the extracts' times in microseconds (their clock: the IMU file's utime).
"""
import json
import math
import os
import shutil
import sys

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import make_format_fixtures as fx  # noqa: E402  (the devkits' schemas)

# Extract folder -> nuScenes channel, in the devkit's order (the native reader's).
NUSCENES_CHANNELS = [("front", "RADAR_FRONT"), ("left", "RADAR_FRONT_LEFT"),
                     ("right", "RADAR_FRONT_RIGHT"), ("rear_left", "RADAR_BACK_LEFT"),
                     ("rear_right", "RADAR_BACK_RIGHT")]
RADARSCENES_SENSORS = [1, 2, 3, 4]
# ../shared/data/real/README.md: sensors.json's x, y [m], yaw [rad] of each radar.
RADARSCENES_MOUNTS = {1: (3.663, -0.873, -1.48418552), 2: (3.86, -0.70, -0.436185662),
                      3: (3.86, 0.70, 0.436), 4: (3.663, 0.873, 1.484)}
VEHICLE = """vehicle:
  model: ackermann
  half_wheelbase_m: 1.3
  model_noise:
    sigma_lateral_mps: 0.2
  velocity_prior:
    enabled: true
    sigma_lateral_mps: 0.2
    sigma_vertical_mps: 0.1
radar:
  geometry: planar
"""


def us(t):
    return int(round(t * 1e6))


def load(folder):
    names = sorted(f for f in os.listdir(os.path.join(folder, "scans")) if f.endswith(".bin"))
    times = np.loadtxt(os.path.join(folder, "times.txt"), ndmin=1)
    scans = [np.fromfile(os.path.join(folder, "scans", n), dtype="<f4").reshape(-1, 6)
             for n in names]
    return list(times), scans


def interpolate(gt, t):
    """The TUM pose at t: position linear, rotation slerp; [x y z qw qx qy qz] (nuScenes' order)."""
    i = int(np.clip(np.searchsorted(gt[:, 0], t), 1, len(gt) - 1))
    a, b = gt[i - 1], gt[i]
    s = float(np.clip((t - a[0]) / (b[0] - a[0]), 0.0, 1.0))
    p = a[1:4] + s * (b[1:4] - a[1:4])
    qa, qb = a[4:8], b[4:8].copy()
    if np.dot(qa, qb) < 0:
        qb = -qb
    angle = math.acos(min(1.0, float(np.dot(qa, qb))))
    if angle < 1e-12:
        q = qa
    else:
        q = (math.sin((1 - s) * angle) * qa + math.sin(s * angle) * qb) / math.sin(angle)
    q = q / np.linalg.norm(q)
    return [float(p[0]), float(p[1]), float(p[2]), float(q[3]), float(q[0]), float(q[1]),
            float(q[2])]


def sweep_records(rows):
    """The ARS408 clusters of one extract scan, the velocity along the line of sight."""
    r = np.zeros(len(rows), fx.pcd_dtype())
    x, y = rows[:, 0].astype(np.float64), rows[:, 1].astype(np.float64)
    d = np.hypot(x, y)
    r["x"], r["y"], r["z"] = rows[:, 0], rows[:, 1], rows[:, 2]
    r["vx"], r["vy"] = rows[:, 4] * x / d, rows[:, 4] * y / d
    r["rcs"], r["dyn_prop"] = rows[:, 3], rows[:, 5]
    r["id"] = np.arange(len(rows))
    r["ambig_state"], r["is_quality_valid"] = 3, 1
    return r


def nuscenes(shared, out):
    base = os.path.join(shared, "nuscenes_scene-0061")
    gt = np.loadtxt(os.path.join(base, "ground_truth.tum"))
    mounts = {}
    for line in open(os.path.join(base, "mounts.txt")):
        if not line.startswith("#"):
            v = line.split()
            mounts[v[0]] = [float(x) for x in v[1:]]  # tx ty tz qx qy qz qw
    tables = {k: [] for k in ["scene", "sample", "sample_data", "sensor", "calibrated_sensor",
                              "ego_pose", "log"]}
    tables["log"].append({"token": "log0", "logfile": "n015", "vehicle": "n015",
                          "date_captured": "2018-07-24", "location": "singapore-onenorth"})
    for ch in ["CAM_FRONT", "LIDAR_TOP"] + [c for _, c in NUSCENES_CHANNELS]:
        modality = "camera" if ch.startswith("CAM") else "lidar" if ch == "LIDAR_TOP" else "radar"
        tables["sensor"].append({"token": "sensor_" + ch, "channel": ch, "modality": modality})
    for name, ch in NUSCENES_CHANNELS:
        m = mounts[name]
        tables["calibrated_sensor"].append({
            "token": "cs_" + ch, "sensor_token": "sensor_" + ch, "translation": m[:3],
            "rotation": [m[6], m[3], m[4], m[5]], "camera_intrinsic": []})
    tables["calibrated_sensor"].append({
        "token": "cs_LIDAR_TOP", "sensor_token": "sensor_LIDAR_TOP", "translation": [0.9, 0, 1.8],
        "rotation": [1.0, 0.0, 0.0, 0.0], "camera_intrinsic": []})
    radars = {ch: load(os.path.join(base, "radar_" + name)) for name, ch in NUSCENES_CHANNELS}
    end = max(times[-1] for times, _ in radars.values()) + 0.5
    later = 1000.0  # scene-0103: the front radar's first sweeps again, this much later [s]
    for s, (scene, first) in enumerate([("scene-0061", 0.0), ("scene-0103", later)]):
        tables["scene"].append({"token": "scene%d" % s, "name": scene, "log_token": "log0",
                                "description": "", "nbr_samples": 0, "first_sample_token": "",
                                "last_sample_token": ""})
        for k in range(int(end / 0.5) + 1):
            tables["sample"].append({"token": "sample%d_%d" % (s, k), "timestamp": us(first + 0.5 * k),
                                     "scene_token": "scene%d" % s, "prev": "", "next": "",
                                     "data": {}, "anns": []})

    def sample_of(s, t):
        return "sample%d_%d" % (s, min(int(round(t / 0.5)), int(end / 0.5)))

    def add(token, channel, t, filename, scene, t_scene):
        tables["ego_pose"].append({"token": "ego_" + token, "timestamp": us(t),
                                   "translation": interpolate(gt, t_scene)[:3],
                                   "rotation": interpolate(gt, t_scene)[3:]})
        tables["sample_data"].append({
            "token": token, "sample_token": sample_of(scene, t_scene), "ego_pose_token":
            "ego_" + token, "calibrated_sensor_token": "cs_" + channel, "timestamp": us(t),
            "fileformat": filename.rsplit(".", 1)[-1], "is_key_frame": False, "height": 0,
            "width": 0, "filename": filename, "prev": "", "next": ""})

    for _, ch in NUSCENES_CHANNELS:
        os.makedirs(os.path.join(out, "sweeps", ch), exist_ok=True)
        times, scans = radars[ch]
        for k, (t, rows) in enumerate(zip(times, scans)):
            name = "sweeps/%s/n015-2018-07-24__%s__%d.pcd" % (ch, ch, us(t))
            fx.write_pcd(os.path.join(out, name), sweep_records(rows))
            add("%s_%d" % (ch, k), ch, t, name, 0, t)
            if ch == "RADAR_FRONT" and k < 40:
                add("%s_later_%d" % (ch, k), ch, t + later, name, 1, t)
    for i, row in enumerate(gt):
        add("lidar_%d" % i, "LIDAR_TOP", row[0], "sweeps/LIDAR_TOP/%d.pcd.bin" % i, 0, row[0])
    os.makedirs(os.path.join(out, "v1.0-mini"), exist_ok=True)
    for name, records in tables.items():
        with open(os.path.join(out, "v1.0-mini", name + ".json"), "w") as f:
            json.dump(records, f, indent=0)
    os.makedirs(os.path.join(out, "can_bus"), exist_ok=True)
    shutil.copy(os.path.join(base, "can_bus", "scene-0061_ms_imu.json"),
                os.path.join(out, "can_bus"))


def radarscenes(shared, out):
    data = os.path.join(out, "data")
    drives = {i: load(os.path.join(shared, "radarscenes_105_radar%d" % i))
              for i in RADARSCENES_SENSORS}
    events = sorted(((us(t), i, rows) for i, (times, scans) in drives.items()
                     for t, rows in zip(times, scans)), key=lambda e: (e[0], e[1]))
    reference = np.concatenate([np.loadtxt(os.path.join(shared, "radarscenes_105_radar%d" % i,
                                                        "reference.tum"))
                                for i in RADARSCENES_SENSORS])
    stamps, first = np.unique([us(t) for t in reference[:, 0]], return_index=True)
    reference = reference[first]

    # range_sc and azimuth_sc as float64: x, y come back to the extracts' float32 values within
    # ~1e-13 m. In the devkit's float32 they come back within ~1e-6 m, which the mapper carries over
    # 2 km of driving into metres (a RANSAC or correspondence decision that flips), and the test is
    # of the reader, not of that sensitivity.
    dtype = np.dtype([(n, "<f8" if n in ("range_sc", "azimuth_sc") else fx.RADAR_DTYPE[n])
                      for n in fx.RADAR_DTYPE.names])

    def write_sequence(name, events):
        seq = os.path.join(data, name)
        os.makedirs(seq, exist_ok=True)
        rows, scenes, first_row = [], {}, 0
        for ts, sensor, s in events:
            r = np.zeros(len(s), dtype)
            r["timestamp"], r["sensor_id"] = ts, sensor
            r["range_sc"] = np.hypot(s[:, 0].astype(np.float64), s[:, 1].astype(np.float64))
            r["azimuth_sc"] = np.arctan2(s[:, 1].astype(np.float64), s[:, 0].astype(np.float64))
            r["rcs"], r["vr"], r["label_id"] = s[:, 3], s[:, 4], s[:, 5]
            mx, my, myaw = RADARSCENES_MOUNTS[sensor]
            r["x_cc"] = mx + math.cos(myaw) * s[:, 0] - math.sin(myaw) * s[:, 1]
            r["y_cc"] = my + math.sin(myaw) * s[:, 0] + math.cos(myaw) * s[:, 1]
            r["track_id"] = b""
            rows.append(r)
            scenes[str(ts)] = {"sensor_id": int(sensor), "radar_indices": [first_row,
                                                                         first_row + len(s)],
                               "odometry_timestamp": int(ts), "odometry_index": 0,
                               "image_name": "%d.jpg" % ts}
            first_row += len(s)
        odometry = np.zeros(len(reference), fx.ODOMETRY_DTYPE)
        odometry["timestamp"] = stamps
        odometry["x_seq"], odometry["y_seq"] = reference[:, 1], reference[:, 2]
        odometry["yaw_seq"] = 2 * np.arctan2(reference[:, 6], reference[:, 7])
        with h5py.File(os.path.join(seq, "radar_data.h5"), "w") as f:
            f.create_dataset("radar_data", data=np.concatenate(rows))
            f.create_dataset("odometry", data=odometry)
        keys = sorted(scenes, key=int)
        with open(os.path.join(seq, "scenes.json"), "w") as f:
            json.dump({"sequence_name": name, "category": "train", "first_timestamp": int(keys[0]),
                       "last_timestamp": int(keys[-1]), "scenes": scenes}, f)

    write_sequence("sequence_105", events)
    write_sequence("sequence_106", events[:100])
    with open(os.path.join(data, "sensors.json"), "w") as f:
        json.dump({"radar_%d" % i: {"id": i, "x": m[0], "y": m[1], "yaw": m[2]}
                   for i, m in RADARSCENES_MOUNTS.items()}, f)


def descriptions(shared, out):
    base = os.path.join(shared, "nuscenes_scene-0061")
    mounts = {}
    for line in open(os.path.join(base, "mounts.txt")):
        if not line.startswith("#"):
            v = line.split()
            mounts[v[0]] = v[1:]
    folder = ("reader: folder\nfolder:\n  scans_dir: %s/scans\n  extension: .bin\n"
              "  timestamps_file: %s/times.txt\n  columns: [x, y, z, rcs, v_r, _]\n"
              "fields: {x: x, y: y, z: z, range: \"\", azimuth: \"\", elevation: \"\", power: rcs, "
              "doppler: v_r, doppler_sign: 1}\n")
    first = os.path.join(base, "radar_front")
    text = folder % (first, first) + "imu: {path: %s, format: nuscenes_can_bus}\n" % os.path.join(
        base, "can_bus", "scene-0061_ms_imu.json")
    m = mounts["front"]
    text += ("extrinsics:\n  T_base_radar: {translation_m: [%s, %s, %s], quaternion_xyzw: [%s, %s, "
             "%s, %s]}\n" % tuple(m)) + VEHICLE + "radars:\n"
    for name, ch in NUSCENES_CHANNELS:
        d = os.path.join(base, "radar_" + name)
        text += ("  - {name: %s, scans_dir: %s/scans, timestamps_file: %s/times.txt, T_base_radar: "
                 "{translation_m: [%s, %s, %s], quaternion_xyzw: [%s, %s, %s, %s]}}\n"
                 % ((ch, d, d) + tuple(mounts[name])))
    open(os.path.join(out, "nuscenes_extracts.yaml"), "w").write(text)
    open(os.path.join(out, "nuscenes_native.yaml"), "w").write(
        "reader: nuscenes\nnuscenes: {dataroot: nuscenes, version: v1.0-mini, scene: scene-0061}\n"
        + VEHICLE)
    first = os.path.join(shared, "radarscenes_105_radar1")
    text = folder % (first, first)
    mx, my, myaw = RADARSCENES_MOUNTS[1]
    text += ("extrinsics:\n  T_base_radar: {translation_m: [%r, %r, 0], rotation_rpy_deg: [0, 0, %r]}\n"
             % (mx, my, math.degrees(myaw))) + VEHICLE + "radars:\n"
    for i in RADARSCENES_SENSORS:
        d = os.path.join(shared, "radarscenes_105_radar%d" % i)
        mx, my, myaw = RADARSCENES_MOUNTS[i]
        text += ("  - {name: radar_%d, scans_dir: %s/scans, timestamps_file: %s/times.txt, "
                 "T_base_radar: {translation_m: [%r, %r, 0], rotation_rpy_deg: [0, 0, %r]}}\n"
                 % (i, d, d, mx, my, math.degrees(myaw)))
    open(os.path.join(out, "radarscenes_extracts.yaml"), "w").write(text)
    open(os.path.join(out, "radarscenes_native.yaml"), "w").write(
        "reader: radarscenes\nradarscenes: {sequence_dir: RadarScenes/data/sequence_105}\n" + VEHICLE)


def variants(out):
    tables = os.path.join(out, "nuscenes", "v1.0-mini")
    nocal = os.path.join(out, "nuscenes", "v1.0-nocal")
    shutil.copytree(tables, nocal)
    records = json.load(open(os.path.join(tables, "calibrated_sensor.json")))
    json.dump([r for r in records if r["token"] != "cs_RADAR_BACK_LEFT"],
              open(os.path.join(nocal, "calibrated_sensor.json"), "w"))
    nopcd = os.path.join(out, "nuscenes", "v1.0-nopcd")
    shutil.copytree(tables, nopcd)
    records = json.load(open(os.path.join(tables, "sample_data.json")))
    for r in records:
        if r["token"] == "RADAR_FRONT_3":
            r["filename"] = "sweeps/RADAR_FRONT/absent.pcd"
    json.dump(records, open(os.path.join(nopcd, "sample_data.json"), "w"))
    twocal = os.path.join(out, "nuscenes", "v1.0-twocal")
    shutil.copytree(tables, twocal)
    records = json.load(open(os.path.join(tables, "calibrated_sensor.json")))
    second = dict(next(r for r in records if r["token"] == "cs_RADAR_FRONT"), token="cs_front_b")
    json.dump(records + [second], open(os.path.join(twocal, "calibrated_sensor.json"), "w"))
    records = json.load(open(os.path.join(tables, "sample_data.json")))
    for r in records:
        if r["token"].startswith("RADAR_FRONT_1"):  # sweeps 1, 10..19, 100..199
            r["calibrated_sensor_token"] = "cs_front_b"
    json.dump(records, open(os.path.join(twocal, "sample_data.json"), "w"))
    data = os.path.join(out, "RadarScenes", "data")
    os.makedirs(os.path.join(data, "sequence_107"))
    shutil.copy(os.path.join(data, "sequence_106", "scenes.json"),
                os.path.join(data, "sequence_107"))


def main():
    shared, out = sys.argv[1], sys.argv[2]
    if os.path.exists(out):
        shutil.rmtree(out)
    os.makedirs(out)
    nuscenes(shared, os.path.join(out, "nuscenes"))
    radarscenes(shared, os.path.join(out, "RadarScenes"))
    descriptions(shared, out)
    variants(out)
    print("devkit copies of %s in %s" % (shared, out))


if __name__ == "__main__":
    main()

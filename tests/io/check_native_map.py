#!/usr/bin/python3
"""`dorado map --prior doppler` with every radar gives the same trajectory from the data sets' own
layouts (reader nuscenes, reader radarscenes; devkit copies written by make_devkit_copies.py) as
from the converted extract folders (reader folder with a radars: list).

  check_native_map.py DORADO SHARED_REAL_DIR OUT_DIR
Prints per data set the poses and the largest position difference; fails when the stamps differ or
a position differs by more than 1 mm, or when a bad --scene / --sequence / --radars does not exit 1
with a message naming what there is. The shipped descriptions (configs/native/*.yaml) run on the
copies with `--data ROOT` and `--scene` / `--sequence` alone, from another working directory, and
give the same trajectories. Exit 77 (skipped) without the shared drives (DORADO_SHARED_REAL names
another place).
"""
import os
import subprocess
import sys

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def map_run(dorado, args, run, cwd=None):
    """`dorado map ARGS --prior doppler --no-loops --out RUN`: its trajectory, or None after saying
    why. (What is compared is what the readers give the mapper: loop closure, the same on both,
    only adds time: the test took 388 s under ASan with it, 271 s without.)"""
    result = subprocess.run([dorado, "map"] + args + ["--prior", "doppler", "--no-loops", "--accept-implausible",
                                                      "--out", run], cwd=cwd, capture_output=True, text=True)
    if result.returncode != 0:
        print("dorado map %s: exit %d: %s" % (" ".join(args), result.returncode,
                                              result.stderr.strip().splitlines()[-1:]))
        return None
    return np.loadtxt(os.path.join(run, "trajectory.tum"), ndmin=2)


def main(dorado, shared, out):
    dorado, out = os.path.abspath(dorado), os.path.abspath(out)
    shared = os.path.abspath(os.environ.get("DORADO_SHARED_REAL", shared))
    if not os.path.isfile(os.path.join(shared, "nuscenes_scene-0061", "mounts.txt")):
        print("skipped: the shared real drives are absent (%s)" % shared)
        return 77
    subprocess.run([sys.executable, os.path.join(HERE, "make_devkit_copies.py"), shared, out],
                   check=True, stdout=subprocess.DEVNULL)
    failed = False
    for data_set in ("nuscenes", "radarscenes"):
        trajectories = {}
        for layout in ("native", "extracts"):
            trajectories[layout] = map_run(
                dorado, [os.path.join(out, "%s_%s.yaml" % (data_set, layout))],
                os.path.join(out, "%s_%s_map" % (data_set, layout)))
        # The shipped description, the release's root as --data, from another folder.
        shipped = os.path.join(HERE, "..", "..", "configs", "native", data_set + ".yaml")
        root, choice = ((os.path.join(out, "nuscenes"), ["--scene", "scene-0061"])
                        if data_set == "nuscenes" else
                        (os.path.join(out, "RadarScenes"), ["--sequence", "105"]))
        os.makedirs(os.path.join(out, "elsewhere"), exist_ok=True)
        trajectories["shipped"] = map_run(dorado, [shipped, "--data", root] + choice,
                                          os.path.join(out, "%s_shipped_map" % data_set),
                                          cwd=os.path.join(out, "elsewhere"))
        if any(t is None for t in trajectories.values()):
            failed = True
            continue
        if not np.array_equal(trajectories["shipped"], trajectories["native"]):
            print("%s: the shipped description with --data gives another trajectory" % data_set)
            failed = True
        a, b = trajectories["native"], trajectories["extracts"]
        if a.shape != b.shape or not np.array_equal(a[:, 0], b[:, 0]):
            print("%s: %d poses native, %d from the extracts, or other stamps"
                  % (data_set, len(a), len(b)))
            failed = True
            continue
        difference = float(np.max(np.linalg.norm(a[:, 1:4] - b[:, 1:4], axis=1)))
        path = float(np.sum(np.linalg.norm(np.diff(b[:, 1:4], axis=0), axis=1)))
        print("%s: %d poses, max |difference| %.3g m (path %.0f m)"
              % (data_set, len(a), difference, path))
        failed = failed or not difference <= 1e-3
    # Bad choices on the command line: exit 1 with the file, what there is and the nearest name.
    for args, expected in (
            (["info", "nuscenes_native.yaml", "--scene", "scene-061"],
             ["nuscenes_native.yaml", "scene.json: no scene named 'scene-061'",
              "the scenes: scene-0061, scene-0103", "did you mean 'scene-0061'?"]),
            (["map", "radarscenes_native.yaml", "--sequence", "108", "--out", "unused"],
             ["--sequence 108", "sequence_108 is not a folder", "did you mean sequence_105?"]),
            (["map", "nuscenes_native.yaml", "--radars", "RADAR_FRONT_LFET", "--out", "unused"],
             ["--radars RADAR_FRONT_LFET: no such radar", "RADAR_FRONT_LEFT"])):
        result = subprocess.run([dorado] + args, cwd=out, capture_output=True, text=True)
        missing = [e for e in expected if e not in result.stderr]
        print("dorado %s: exit %d%s" % (" ".join(args[:4]), result.returncode,
                                        ", missing %s in: %s" % (missing, result.stderr)
                                        if missing else ""))
        failed = failed or result.returncode != 1 or bool(missing)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main(*sys.argv[1:4]))

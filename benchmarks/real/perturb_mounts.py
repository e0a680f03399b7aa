#!/usr/bin/python3
"""Mount perturbations for the multi-radar runs (dorado map / dorado twist on a `radars:` list).

    benchmarks/real/perturb_mounts.py write DATASET.yaml OUT.yaml [--delta-deg 0.5] [--sign 1]
        A copy of the description with every radar's yaw turned by +-delta (alternating, the first
        by sign * delta), its data_dir: made absolute.
    benchmarks/real/perturb_mounts.py compare RUN_DIR PERTURBED_RUN_DIR [--delta-deg 0.5] [--sign 1]
        Each radar's recovered yaw (published + the run's estimated offset, summary.json) in the
        perturbed run against the unperturbed run's: one table row, the largest difference [deg].
"""
import argparse
import json
import math
import os

import yaml


def deltas(count, delta_deg, sign):
    return [sign * delta_deg * (1 if k % 2 == 0 else -1) for k in range(count)]


def yaw_deg(mount):
    if "quaternion_xyzw" in mount:
        q = mount["quaternion_xyzw"]
        return math.degrees(2.0 * math.atan2(q[2], q[3]))
    return float(mount["rotation_rpy_deg"][2])


def write(args):
    base = os.path.dirname(os.path.abspath(args.dataset))
    with open(args.dataset) as f:
        config = yaml.safe_load(f)

    # The copy lives elsewhere: its relative paths are taken from the original's data folder.
    config["data_dir"] = os.path.normpath(os.path.join(base, config.get("data_dir") or "."))
    radars = config.get("radars") or []
    if len(radars) < 2:
        raise SystemExit("%s: key 'radars': needs a list of >= 2 radars" % args.dataset)
    for radar, d in zip(radars, deltas(len(radars), args.delta_deg, args.sign)):
        mount = radar["T_base_radar"]
        yaw = yaw_deg(mount) + d
        mount.pop("quaternion_xyzw", None)
        mount["rotation_rpy_deg"] = [0.0, 0.0, yaw]
    with open(args.out, "w") as f:
        f.write("# %s with every radar's yaw turned by %+g / %+g deg (alternating)\n"
                % (args.dataset, args.sign * args.delta_deg, -args.sign * args.delta_deg))
        yaml.safe_dump(config, f, sort_keys=False)


def compare(args):
    runs = []
    for d in (args.run_dir, args.perturbed_run_dir):
        with open(os.path.join(d, "summary.json")) as f:
            runs.append(json.load(f)["radars"])
    d = deltas(len(runs[0]), args.delta_deg, args.sign)
    # The perturbed run starts from published + d; it recovers published + d + offset.
    diffs = [(p["mount_yaw_offset_deg"] + dk) - u["mount_yaw_offset_deg"]
             for u, p, dk in zip(runs[0], runs[1], d)]
    print("| %s | %s | %.3f |" % (os.path.basename(os.path.normpath(args.perturbed_run_dir)),
                                 ", ".join("%s %+.3f" % (r["name"], x) for r, x in zip(runs[0], diffs)),
                                 max(abs(x) for x in diffs)))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="command", required=True)
    w = sub.add_parser("write")
    w.add_argument("dataset")
    w.add_argument("out")
    c = sub.add_parser("compare")
    c.add_argument("run_dir")
    c.add_argument("perturbed_run_dir")
    for p in (w, c):
        p.add_argument("--delta-deg", type=float, default=0.5)
        p.add_argument("--sign", type=int, choices=[-1, 1], default=1)
    args = ap.parse_args()
    write(args) if args.command == "write" else compare(args)


if __name__ == "__main__":
    main()

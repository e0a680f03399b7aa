#!/usr/bin/python3
"""`dorado calibrate sx` and `calibrate rotation` over seeds: on drives of the right kind the reported
sigma must cover the truth, on drives of the wrong kind the step must refuse.

    benchmarks/calibration/calibration_seeds.py --out DIR [--dorado build/apps/dorado]
        [--seeds 100-109] [--xsim ../shared/xsim] [--table GENERATED.md]

Right kind (dorado simulate, the truth from the sequence's mount):
  - calibrate sx on `calib_circle` (a car circling, s_x = 3.5 m);
  - calibrate rotation on `calib_straight` (straight forward and backward, mount pitch 2, yaw 4 deg).
Wrong kind (each must refuse with exit 1):
  - calibrate sx on xsim `car_road` cut to 20 s with --from 10 --to 40 (the window past the drive's
    end), the same without the window (a nearly straight drive), and on `calib_straight` (no turning);
  - calibrate rotation on xsim `car_road` and `loop` (forward only, curves) and on `calib_circle`.
"Covers" means |estimate - truth| <= 2 sigma (the 95 % interval of the sigma printed). With --table
the results go into GENERATED.md (docs/generated/calibration.md) as the tables docs/calibration.md
quotes (benchmarks/real/doc_tables.py quote). About 5 minutes for 10 seeds on an idle 2-core machine
(the drives are simulated once and kept in --out).
"""
import argparse
import concurrent.futures
import os
import re
import subprocess
import sys

XSIM_DEFAULT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "shared", "xsim")
TRUTH = {"sx": 3.5, "pitch": 2.0, "yaw": 4.0}


def run(cmd, log=None):
    p = subprocess.run(cmd, capture_output=True, text=True)
    if log:
        with open(log, "w") as f:
            f.write(" ".join(cmd) + "\n" + p.stdout + p.stderr)
    return p


def seeds_of(text):
    if "-" in text:
        a, b = text.split("-")
        return list(range(int(a), int(b) + 1))
    return [int(s) for s in text.split(",")]


def simulate(dorado, sequence, seed, out):
    if not os.path.exists(os.path.join(out, "dataset.yaml")):
        p = run([dorado, "simulate", "--sequence", sequence, "--seed", str(seed), "--out", out])
        if p.returncode != 0:
            sys.exit("simulate %s %d failed:\n%s" % (sequence, seed, p.stderr))
    return out


def xsim(xsim_dir, scenario, seed, out, duration):
    if not os.path.exists(os.path.join(out, "dorado.yaml")):
        args = ["/usr/bin/python3", os.path.join(xsim_dir, "make_scenario.py"), "--out", out,
                "--scenario", scenario, "--seed", str(seed)]
        if duration:
            args += ["--duration", str(duration)]
        if run(args).returncode != 0 or run(["/usr/bin/python3", os.path.join(xsim_dir, "describe.py"), out]).returncode != 0:
            sys.exit("xsim %s %d failed" % (scenario, seed))
    return os.path.join(out, "dorado.yaml")


def calibrate(dorado, step, dataset, out, extra=()):
    """(exit code, snippet text, stderr)"""
    if os.path.exists(out):
        os.remove(out)
    p = run([dorado, "calibrate", step, dataset, "--out", out] + list(extra), out + ".log")
    text = open(out).read() if p.returncode == 0 and os.path.exists(out) else ""
    return p.returncode, text, p.stderr


def sx_result(text):
    m = re.search(r"s_x = ([-\d.e]+) \+- ([\d.e]+) m", text)
    return float(m.group(1)), float(m.group(2))


def rotation_result(text):
    rpy = re.search(r"rotation_rpy_deg: \[([^\]]*)\]", text).group(1).split(",")
    sigma = float(re.search(r"angle sigma ([\d.e-]+) deg", text).group(1))
    return float(rpy[1]), float(rpy[2]), sigma


def one_seed(a, seed):
    w = lambda name: os.path.join(a.out, "%s_%d" % (name, seed))
    circle = simulate(a.dorado, "calib_circle", seed, w("circle"))
    straight = simulate(a.dorado, "calib_straight", seed, w("straight"))
    road = xsim(a.xsim, "car_road", seed, w("xsim_car_road20"), 20)
    loop = xsim(a.xsim, "loop", seed, w("xsim_loop60"), 60)
    r = {"seed": seed}
    code, text, err = calibrate(a.dorado, "sx", circle, w("sx_circle") + ".yaml")
    r["sx"] = sx_result(text) if code == 0 else None
    r["sx_err"] = err.strip().splitlines()[-1] if code != 0 else ""
    code, text, err = calibrate(a.dorado, "rotation", straight, w("rot_straight") + ".yaml")
    r["rot"] = rotation_result(text) if code == 0 else None
    r["rot_err"] = err.strip().splitlines()[-1] if code != 0 else ""
    wrong = {
        "sx: xsim car_road 20 s, --from 10 --to 40": ("sx", road, ["--from", "10", "--to", "40"]),
        "sx: xsim car_road 20 s": ("sx", road, []),
        "sx: calib_straight": ("sx", straight, []),
        "rotation: xsim car_road 20 s": ("rotation", road, []),
        "rotation: xsim loop 60 s": ("rotation", loop, []),
        "rotation: calib_circle": ("rotation", circle, []),
    }
    r["wrong"] = {}
    for name, (step, data, extra) in wrong.items():
        code, _, err = calibrate(a.dorado, step, data, w("wrong_" + re.sub(r"\W+", "_", name)) + ".yaml", extra)
        r["wrong"][name] = (code, err.strip().splitlines()[-1] if err.strip() else "")
    return r


def tables(results):
    n = len(results)
    seeds = "%d-%d" % (results[0]["seed"], results[-1]["seed"])
    out = ["<!-- table calibration_right_kind -->",
           "| step, drive (%d seeds, %s) | truth | estimates (min .. max) | sigma (median) | max abs error | covered (error <= 2 sigma) | refused |" % (n, seeds),
           "|---|---:|---|---:|---:|---:|---:|"]
    sx = [r["sx"] for r in results if r["sx"]]
    if sx:
        errs = [abs(v - TRUTH["sx"]) for v, _ in sx]
        cov = sum(abs(v - TRUTH["sx"]) <= 2 * s for v, s in sx)
        out.append("| `calibrate sx`, `calib_circle` | s_x %.2f m | %.3f .. %.3f m | %.3f m | %.3f m | %d of %d | %d |" % (
            TRUTH["sx"], min(v for v, _ in sx), max(v for v, _ in sx), sorted(s for _, s in sx)[len(sx) // 2],
            max(errs), cov, n, n - len(sx)))
    rot = [r["rot"] for r in results if r["rot"]]
    if rot:
        for k, name in ((0, "pitch"), (1, "yaw")):
            errs = [abs(x[k] - TRUTH[name]) for x in rot]
            cov = sum(abs(x[k] - TRUTH[name]) <= 2 * x[2] for x in rot)
            out.append("| `calibrate rotation`, `calib_straight` (%s) | %.1f deg | %.3f .. %.3f deg | %.3f deg | %.3f deg | %d of %d | %d |" % (
                name, TRUTH[name], min(x[k] for x in rot), max(x[k] for x in rot),
                sorted(x[2] for x in rot)[len(rot) // 2], max(errs), cov, n, n - len(rot)))
    out.append("<!-- end table -->")
    out += ["", "<!-- table calibration_wrong_kind -->",
            "| step, drive (%d seeds, %s) | refused (exit 1) | the first seed's reason |" % (n, seeds),
            "|---|---:|---|"]
    for name in results[0]["wrong"]:
        refused = sum(r["wrong"][name][0] == 1 for r in results)
        reason = results[0]["wrong"][name][1].replace("|", "/")
        reason = re.sub(r"^dorado: error: \S+: ", "", reason)
        out.append("| %s | %d of %d | %s |" % (name, refused, n, reason))
    out.append("<!-- end table -->")
    return "\n".join(out) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True)
    ap.add_argument("--dorado", default="build/apps/dorado")
    ap.add_argument("--seeds", default="100-109")
    ap.add_argument("--xsim", default=XSIM_DEFAULT)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--table", help="write the tables into this generated markdown file")
    a = ap.parse_args()
    a.dorado = os.path.abspath(a.dorado)
    os.makedirs(a.out, exist_ok=True)
    with concurrent.futures.ThreadPoolExecutor(a.jobs) as pool:
        results = list(pool.map(lambda s: one_seed(a, s), seeds_of(a.seeds)))
    for r in results:
        print("seed %d: sx %s %s | rotation %s %s | wrong: %s" % (
            r["seed"], r["sx"], r["sx_err"], r["rot"], r["rot_err"],
            ", ".join("%s=%d" % (k.split(":")[0], v[0]) for k, v in r["wrong"].items())))
    text = tables(results)
    print(text)
    if a.table:
        with open(a.table, "w") as f:
            f.write("# Calibration over seeds (generated)\n\nGenerated by `benchmarks/calibration/calibration_seeds.py`"
                    " with %s; do not edit. docs/calibration.md quotes it.\n\n" % run([a.dorado, "--version"]).stdout.strip())
            f.write(text)


if __name__ == "__main__":
    main()

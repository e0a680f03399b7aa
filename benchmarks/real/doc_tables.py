#!/usr/bin/python3
"""Tables of benchmarks/real/run_real.sh's runs for docs/generated/real_recordings.md.

    doc_tables.py ti OUT_DIR                 the TI hand-held recording: odometry, map, loop closure
    doc_tables.py times OUT_DIR NAME...      the map's time per sweep / scan of each run [ms]
    doc_tables.py bench RESULTS_MD SECTION [--drop-time]   the table of one sequence of `dorado bench`'s
                                             results.md, verbatim (without the time per scan)
    doc_tables.py bench_axis RESULTS_MD      results.md's rotation error by body axis (pooled), verbatim
    doc_tables.py xsim RESULTS_MD            run_xsim.py's results.md: its tables and pooled line, verbatim
    doc_tables.py quote GENERATED PAGE...    copies GENERATED's tables into each PAGE's quoted blocks

A generated table sits between `<!-- table NAME -->` and `<!-- end table -->`; a page quotes it between
`<!-- quoted from generated/FILE.md: NAME -->` and `<!-- end quote -->` (tests/docs/test_quoted_tables.cpp checks
that they agree).
"""
import json
import os
import re
import sys

import numpy as np


def summary(run_dir):
    with open(os.path.join(run_dir, "summary.json")) as f:
        return json.load(f)


def loop_gap(run_dir):
    """Horizontal and vertical distance between the trajectory's first and last pose [m]."""
    a = np.loadtxt(os.path.join(run_dir, "trajectory.tum"), comments="#", ndmin=2)
    d = a[-1, 1:4] - a[0, 1:4]
    return float(np.hypot(d[0], d[1])), float(abs(d[2]))


def ti(out):
    odo, mp, cv = (os.path.join(out, n) for n in ("ti_odo", "ti_map", "ti_map_constvel"))
    so, sm = summary(odo), summary(mp)
    reasons = ", ".join('"%s"' % k for k in sm.get("fallback_reasons", {}))
    rows = [
        ("`dorado odometry --method imu+doppler`",
         "%d of %d scans valid, %d fallbacks, %d zero-velocity updates, %.2f ms per scan (mean), path %.1f m"
         % (so["scans_used"], so["scans"], so["scans_with_fallback_twist"], so["scans_zero_velocity_update"],
            so["time_per_scan_ms"]["mean"], so["path_length_m"])),
        ("`dorado map --prior imu+doppler` with `mapper_sparse.yaml`",
         "%d of %d scans fall back%s, %.2f ms per scan (median), %d map points"
         % (sm["fallbacks"], sm["scans"], " (%s)" % reasons if reasons else "",
            sm["time_per_scan_ms"]["median"], sm["map_points"])),
        ("loop closure: last pose to first (rests at both ends, so probably put back where it started)",
         "odometry %.2f m horizontally, %.2f m vertically; map %.2f m, %.2f m" % (loop_gap(odo) + loop_gap(mp))),
        ("`dorado map --prior constvel` (radar only)", "ends %.1f m from its start" % np.hypot(*loop_gap(cv))),
    ]
    print("| what | measured |\n|---|---|")
    for what, measured in rows:
        print("| %s | %s |" % (what, measured))


def times(out, names):
    print("| run | mean [ms] | median [ms] | p95 [ms] |\n|---|---:|---:|---:|")
    for name in names:
        t = summary(os.path.join(out, name))["time_per_scan_ms"]
        print("| %s | %.3f | %.3f | %.3f |" % (name, t["mean"], t["median"], t["p95"]))


def bench(results_md, section, drop_time=False):
    with open(results_md) as f:
        text = f.read()
    m = re.search(r"^## %s\n\n((?:\|.*\n)+)" % re.escape(section), text, re.M)
    if not m:
        sys.exit("%s: no table under '## %s'" % (results_md, section))
    table = m.group(1)
    if drop_time:  # the machine's time per scan: docs/speed.md prints it with the machine
        rows = [line.rstrip("\n").rstrip("|").split("|") for line in table.splitlines()]
        keep = [i for i, cell in enumerate(rows[0]) if "time/scan" not in cell]
        table = "".join("|".join(row[i] for i in keep if i < len(row)) + "|\n" for row in rows)
    sys.stdout.write(table)


def bench_axis(results_md):
    with open(results_md) as f:
        text = f.read()
    m = re.search(r"^Rotation error by body axis.*\n\n((?:\|.*\n)+)", text, re.M)
    if not m:
        sys.exit("%s: no rotation-by-axis table" % results_md)
    sys.stdout.write(m.group(1))


def xsim(results_md):
    """From the first kind's table on: not the preamble (the output folder, the binary, seconds)."""
    with open(results_md) as f:
        text = f.read().strip()
    start = text.find("### ")
    if start < 0:
        sys.exit("%s: no kind's table" % results_md)
    sys.stdout.write(text[start:] + "\n")


TABLE = re.compile(r"<!-- table (\S+) -->\n(.*?)<!-- end table -->\n", re.S)
QUOTE = re.compile(r"(<!-- quoted from generated/(\S+): (\S+) -->\n)(.*?)(<!-- end quote -->)", re.S)


def quote(generated, pages):
    with open(generated) as f:
        tables = dict(TABLE.findall(f.read()))
    name = os.path.basename(generated)
    for page in pages:
        with open(page) as f:
            text = f.read()

        def replace(m):
            if m.group(2) != name:
                return m.group(0)
            if m.group(3) not in tables:
                sys.exit("%s: quotes %s: %s, which %s does not hold" % (page, name, m.group(3), generated))
            return m.group(1) + tables[m.group(3)] + m.group(5)

        with open(page, "w") as f:
            f.write(QUOTE.sub(replace, text))


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    kind, args = sys.argv[1], sys.argv[2:]
    if kind == "ti":
        ti(args[0])
    elif kind == "times":
        times(args[0], args[1:])
    elif kind == "bench":
        bench(args[0], args[1], "--drop-time" in args[2:])
    elif kind == "bench_axis":
        bench_axis(args[0])
    elif kind == "xsim":
        xsim(args[0])
    elif kind == "quote":
        quote(args[0], args[1:])
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()

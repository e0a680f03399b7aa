#!/usr/bin/env bash
# Odometry time per scan of two dorado binaries, side by side on the same simulated sequences
# (a speed-up is judged as the ratio B/A). Runs A and B alternately `reps`
# times per sequence (so that machine load hits both alike) and prints, per sequence, the median
# over runs of summary.json's time_per_scan_ms median and p95, and the ratio B/A.
# The sequences are simulated by A (the baseline, usually the older binary: a newer dorado reads an
# older dataset description, not always the reverse).
# Usage: benchmarks/odometry/compare_odometry_time.sh DORADO_A DORADO_B OUT [reps=3] [duration_s=30]
# B_ARGS (environment) is added to B's command line, e.g. B_ARGS="--config my_odometry.yaml".
set -euo pipefail
A=$1 B=$2 OUT=$3 REPS=${4:-3} DUR=${5:-30}
SEQS=(seq04 seq05 seq06 seq07 seq08 seq11 car_urban side_mount)
mkdir -p "$OUT"
for s in "${SEQS[@]}"; do
  mkdir -p "$OUT/runs/$s"
  [ -f "$OUT/data/$s/dataset.yaml" ] || "$A" simulate --sequence "$s" --duration "$DUR" --out "$OUT/data/$s" >/dev/null
  for r in $(seq "$REPS"); do
    for which in A B; do
      bin=$A extra=()
      [ "$which" = B ] && bin=$B && read -r -a extra <<<"${B_ARGS:-}"
      if ! "$bin" odometry "$OUT/data/$s/dataset.yaml" --out "$OUT/runs/$s/$which$r" "${extra[@]}" >/dev/null \
          2>"$OUT/runs/$s/$which$r.log"; then
        echo "compare_odometry_time.sh: $bin odometry on $s failed:" >&2
        tail -3 "$OUT/runs/$s/$which$r.log" >&2
        exit 1
      fi
    done
  done
done
/usr/bin/python3 - "$OUT" "$REPS" "${SEQS[@]}" <<'PY'
import json, statistics, sys
out, reps, seqs = sys.argv[1], int(sys.argv[2]), sys.argv[3:]
def stat(s, w, key):
    return statistics.median(json.load(open(f"{out}/runs/{s}/{w}{r}/summary.json"))["time_per_scan_ms"][key]
                             for r in range(1, reps + 1))
print(f"{'sequence':12s} {'A median':>9s} {'A p95':>7s} {'B median':>9s} {'B p95':>7s} {'B/A':>6s}")
ratios = []
for s in seqs:
    am, ap, bm, bp = stat(s, "A", "median"), stat(s, "A", "p95"), stat(s, "B", "median"), stat(s, "B", "p95")
    ratios.append(bm / am)
    print(f"{s:12s} {am:9.3f} {ap:7.3f} {bm:9.3f} {bp:7.3f} {bm/am:6.2f}")
print(f"{'pooled':12s} median of B/A = {statistics.median(ratios):.2f} (ms per scan; summary.json time_per_scan_ms)")
PY

#!/usr/bin/env bash
# The covariance that dorado map writes (covariance.csv) against the simulator's exact trajectory:
# its fused 1-frame mean NEES (6 dof) must lie in [3, 12], a band that the same covariance scaled by
# 4 or by 1/4, or set to zero, leaves (checked here too, so the gate is known to bite).
# Usage: test_map_covariance.sh DORADO NEES_SCRIPT
set -euo pipefail
DORADO=$1 NEES=$2
dir=$(mktemp -d /tmp/dorado_cov_XXXXXX)
trap 'rm -rf "$dir"' EXIT
"$DORADO" simulate --sequence seq08 --duration 20 --seed 8 --out "$dir/sim" 2>/dev/null
"$DORADO" map "$dir/sim/dataset.yaml" --prior doppler --out "$dir/map" 2>/dev/null
run=(/usr/bin/python3 "$NEES" --truth "$dir/sim/true_trajectory.tum" --run "$dir/map" --name seq08_20s)
"${run[@]}" --check-fused-nees 3 12
for scale in 4 0.25 0; do
  if "${run[@]}" --scale-covariance "$scale" --check-fused-nees 3 12 >/dev/null 2>&1; then
    echo "FAIL: the covariance scaled by $scale passed the NEES gate"; exit 1
  fi
  echo "ok: the covariance scaled by $scale fails the NEES gate"
done

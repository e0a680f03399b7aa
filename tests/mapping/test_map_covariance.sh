#!/usr/bin/env bash
# The covariance that dorado map writes (covariance.csv) against the simulator's exact trajectory, on
# two recordings of seq08 (mixed route, fast turns; seeds 8 and 108): the fused pose's 1-frame mean NEES of each
# 3-dof block must lie in the chi-square mean 3 within a factor 2 (model error, correlated samples) for the
# rotation, [1.5, 6]; the translation's band is [0.6, 6], because the translation is the Doppler prior's, whose
# covariance is knowingly conservative per frame by two factors of ~2: the direction-noise compensation (EIV, the
# default: 1.87 / 1.46 with it, 2.09 / 1.69 without) and the trapezoid twist (an
# interval's covariance is its share of a sum over many intervals, (C_prev + C) / 2, twice the one frame's,
# because consecutive intervals share a scan; 0.94 / 0.79 with it). docs/covariance.md.
# The fused (written) pose's covariance is its smoothed motion's from the previous written pose: per frame close to
# the prior's (the registration's information per frame is small beside the Doppler prior's; what the smoother
# takes from the map is the drive's, not the frame's), so reporting the prior's covariance is no mutation this gate
# can tell apart any more. Mutations, each of which must fail on EACH sequence:
#   --fused-covariance registration  it reports the registration's covariance alone (it ignores the
#                                    prior): fails in translation, where the registration is far wider;
#   --scale-covariance 4 / 0.25      over- / under-confident by 4: fails by the band's width (a band
#                                    narrower than 16:1 cannot hold both x and 4x or x/4), so these two
#                                    check the gate's width, not the data.
# Usage: test_map_covariance.sh DORADO NEES_SCRIPT
set -euo pipefail
DORADO=$1 NEES=$2
dir=$(mktemp -d /tmp/dorado_cov_XXXXXX)
trap 'rm -rf "$dir"' EXIT
# (On the slow sequences the translation block is over-conservative, NEES 0.2-0.5: the prior's velocity floor;
# on car_urban / fast_flat_open it is 3.0 with the trapezoid twist, ~20 without: docs/covariance.md.)
for spec in seq08:8 seq08:108; do
  seq=${spec%%:*} seed=${spec##*:}
  "$DORADO" simulate --sequence "$seq" --duration 20 --seed "$seed" --out "$dir/sim_$seq$seed" 2>/dev/null
  "$DORADO" map "$dir/sim_$seq$seed/dataset.yaml" --prior doppler --accept-implausible --out "$dir/map_$seq$seed" \
    2>/dev/null
  run=(/usr/bin/python3 "$NEES" --truth "$dir/sim_$seq$seed/true_trajectory.tum" --run "$dir/map_$seq$seed"
       --name "${seq}_s${seed}_20s" --check-block-nees 0.6 6 1.5 6)
  "${run[@]}"
  for mutation in "--fused-covariance registration" \
                  "--scale-covariance 4" "--scale-covariance 0.25"; do
    # shellcheck disable=SC2086
    if "${run[@]}" $mutation >/dev/null 2>&1; then
      echo "FAIL: $seq seed $seed: $mutation passed the NEES gate"; exit 1
    fi
    echo "ok: $seq seed $seed: $mutation fails the NEES gate"
  done
done

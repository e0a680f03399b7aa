#!/bin/bash
# The real 2D-radar recordings (../shared/data/real/, README there) scored against their
# references: `dorado odometry` (planar mode, Doppler only) on RadarScenes 105 radar 3 and on
# nuScenes scene-0061's front radar, then one table row each (benchmarks/real/score_real.py).
#   benchmarks/real/run_real.sh [OUT_DIR] [DORADO]      (from the repository root)
set -euo pipefail
out=${1:-out/real}
dorado=${2:-build/apps/dorado}
mkdir -p "$out"
score=benchmarks/real/score_real.py
"$dorado" odometry configs/radarscenes.yaml --out "$out/radarscenes_odo" --masks 2> "$out/radarscenes_odo.log"
"$dorado" odometry configs/nuscenes.yaml --out "$out/nuscenes_odo" --masks 2> "$out/nuscenes_odo.log"
/usr/bin/python3 $score configs/radarscenes.yaml "$out/radarscenes_odo" --dorado "$dorado" \
    --labels radarscenes --name "RadarScenes 105 radar 3, odometry (doppler)" --header
/usr/bin/python3 $score configs/nuscenes.yaml "$out/nuscenes_odo" --dorado "$dorado" \
    --labels nuscenes --name "nuScenes 0061 front, odometry (doppler)"

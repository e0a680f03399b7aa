#!/bin/bash
# The real 2D-radar recordings (../shared/data/real/, README there) scored against their
# references (benchmarks/real/score_real.py, one table row each): `dorado odometry` (planar
# mode, Doppler only) and `dorado map --prior doppler` (registration in the plane) on RadarScenes
# 105 radar 3 and on nuScenes scene-0061's front radar, and `dorado twist` (all 5 nuScenes radars
# jointly) with its yaw-rate RMSE next to the front radar's kinematic one.
#   benchmarks/real/run_real.sh [OUT_DIR] [DORADO]      (from the repository root)
set -euo pipefail
out=${1:-out/real}
dorado=${2:-build/apps/dorado}
mkdir -p "$out"
score=benchmarks/real/score_real.py
"$dorado" odometry configs/radarscenes.yaml --out "$out/radarscenes_odo" --masks 2> "$out/radarscenes_odo.log"
"$dorado" odometry configs/nuscenes.yaml --out "$out/nuscenes_odo" --masks 2> "$out/nuscenes_odo.log"
for cfg in "" configs/mapper_automotive.yaml; do
    tag=${cfg:+_automotive}
    "$dorado" map configs/radarscenes.yaml --prior doppler ${cfg:+--config $cfg} \
        --out "$out/radarscenes_map$tag" 2> "$out/radarscenes_map$tag.log"
    "$dorado" map configs/nuscenes.yaml --prior doppler ${cfg:+--config $cfg} \
        --out "$out/nuscenes_map$tag" 2> "$out/nuscenes_map$tag.log"
done
"$dorado" twist configs/nuscenes.yaml --out "$out/nuscenes_twist" 2> "$out/nuscenes_twist.log"
/usr/bin/python3 $score configs/radarscenes.yaml "$out/radarscenes_odo" --dorado "$dorado" \
    --labels radarscenes --name "RadarScenes 105 radar 3, odometry (doppler)" --header
/usr/bin/python3 $score configs/radarscenes.yaml "$out/radarscenes_map" --dorado "$dorado" \
    --name "RadarScenes 105 radar 3, map --prior doppler"
/usr/bin/python3 $score configs/radarscenes.yaml "$out/radarscenes_map_automotive" --dorado "$dorado" \
    --name "RadarScenes 105 radar 3, map --prior doppler, mapper_automotive.yaml"
/usr/bin/python3 $score configs/nuscenes.yaml "$out/nuscenes_odo" --dorado "$dorado" \
    --labels nuscenes --name "nuScenes 0061 front, odometry (doppler)"
/usr/bin/python3 $score configs/nuscenes.yaml "$out/nuscenes_map" --dorado "$dorado" \
    --name "nuScenes 0061 front, map --prior doppler"
/usr/bin/python3 $score configs/nuscenes.yaml "$out/nuscenes_map_automotive" --dorado "$dorado" \
    --name "nuScenes 0061 front, map --prior doppler, mapper_automotive.yaml"
echo
/usr/bin/python3 $score configs/nuscenes.yaml "$out/nuscenes_twist" --dorado "$dorado" \
    --name "nuScenes 0061, twist of all 5 radars (dead-reckoned)" --header

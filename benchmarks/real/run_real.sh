#!/bin/bash
# The real 2D-radar recordings (../shared/data/real/, README there) scored against their
# references (benchmarks/real/score_real.py, one table row each):
#   - one radar: `dorado odometry` (planar, Doppler only) and `dorado map --prior doppler` on
#     RadarScenes 105 (each of its four radars alone) and on nuScenes scene-0061's front radar;
#   - every radar: `dorado twist` (the twist filter, each radar at its own time) and `dorado map`
#     (every radar into one map) on RadarScenes 105 (4 radars) and nuScenes 0061 (5 radars), with
#     the mounts calibrated online (default) and with the published ones (--fixed-mounts);
#   - the mounts perturbed: every radar's yaw turned by +-0.5 deg (alternating, both ways), mapped
#     again; the recovered yaws against the unperturbed run's (perturb_mounts.py compare).
#   benchmarks/real/run_real.sh [OUT_DIR] [DORADO]      (from the repository root, ~2 minutes)
set -euo pipefail
out=${1:-out/real}
dorado=${2:-build/apps/dorado}
mkdir -p "$out"
score=benchmarks/real/score_real.py
perturb=benchmarks/real/perturb_mounts.py
rs=configs/radarscenes_all.yaml
nu=configs/nuscenes.yaml

run() {  # run NAME DORADO-ARGS...: one run into $out/NAME, its log beside it
    local name=$1
    shift
    "$dorado" "$@" --out "$out/$name" 2> "$out/$name.log"
}
row() {  # row DATASET NAME TITLE [score args]
    /usr/bin/python3 $score "$1" "$out/$2" --dorado "$dorado" --name "$3" "${@:4}"
}

run rs_odo odometry configs/radarscenes.yaml --masks
run nu_odo odometry $nu --masks
for r in radar1 radar2 radar3 radar4; do run rs_map_$r map $rs --radars $r; done
run rs_map_radar3_automotive map $rs --radars radar3 --config configs/mapper_automotive.yaml
run nu_map_front map $nu --radars first
for d in rs nu; do
    cfg=$rs; [ $d = nu ] && cfg=$nu
    run ${d}_twist twist $cfg
    run ${d}_twist_fixed twist $cfg --fixed-mounts
    run ${d}_map map $cfg
    run ${d}_map_fixed map $cfg --fixed-mounts
    for sign in 1 -1; do
        /usr/bin/python3 $perturb write $cfg "$out/${d}_perturbed$sign.yaml" --sign $sign
        run ${d}_map_perturbed$sign map "$out/${d}_perturbed$sign.yaml"
        run ${d}_map_perturbed${sign}_fixed map "$out/${d}_perturbed$sign.yaml" --fixed-mounts
    done
done

echo "One radar"
row configs/radarscenes.yaml rs_odo "RadarScenes 105 radar 3, odometry (doppler)" --labels radarscenes --header
for r in radar1 radar2 radar3 radar4; do row $rs rs_map_$r "RadarScenes 105 $r, map --prior doppler"; done
row $rs rs_map_radar3_automotive "RadarScenes 105 radar3, map, mapper_automotive.yaml"
row $nu nu_odo "nuScenes 0061 front, odometry (doppler)" --labels nuscenes
row $nu nu_map_front "nuScenes 0061 front, map --prior doppler"
echo
echo "Every radar (twist: the filter's dead reckoning; map: every radar into one map)"
row $rs rs_twist "RadarScenes 105, 4 radars, twist" --header
row $rs rs_twist_fixed "RadarScenes 105, 4 radars, twist --fixed-mounts"
row $nu nu_twist "nuScenes 0061, 5 radars, twist"
row $nu nu_twist_fixed "nuScenes 0061, 5 radars, twist --fixed-mounts"
echo
row $rs rs_map "RadarScenes 105, 4 radars, map" --header
row $rs rs_map_fixed "RadarScenes 105, 4 radars, map --fixed-mounts"
row $nu nu_map "nuScenes 0061, 5 radars, map"
row $nu nu_map_fixed "nuScenes 0061, 5 radars, map --fixed-mounts"
for d in rs nu; do
    for sign in 1 -1; do
        for tag in "" _fixed; do
            row "$out/${d}_perturbed$sign.yaml" ${d}_map_perturbed$sign$tag \
                "$d, every mount +-0.5 deg (sign $sign), map${tag:+ --fixed-mounts}"
        done
    done
done
echo
echo "Recovered mount yaws, perturbed run minus unperturbed run [deg] (largest last)"
for d in rs nu; do
    for sign in 1 -1; do
        /usr/bin/python3 $perturb compare "$out/${d}_map" "$out/${d}_map_perturbed$sign" --sign $sign
    done
done
echo
echo "Time per sweep / scan [ms]"
for name in nu_map_front nu_map rs_map_radar3 rs_map; do
    /usr/bin/python3 -c "import json,sys; s=json.load(open(sys.argv[1])); t=s['time_per_scan_ms']; print('%s: mean %.3f median %.3f p95 %.3f' % (sys.argv[2], t['mean'], t['median'], t['p95']))" "$out/$name/summary.json" $name
done

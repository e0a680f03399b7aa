#!/bin/bash
# Every mapping default is judged on two worlds (docs/robust_mapping.md): the built-in simulator's 12
# sequences (configs/benchmark_fusion.yaml, scored against the exact trajectory) and the independent
# generator ../shared/xsim (its five scenario kinds, three seeds each, each kind's worst seed shown).
#   benchmarks/two_worlds.sh [OUT_DIR] [DORADO] [-- extra `dorado map` args for the xsim doppler map, e.g. --config F]
# Prints the built-in table (benchmarks/mapping/fusion_table.py) and the xsim tables (run_xsim.py); both
# are resumable (a finished run is not run again).
set -euo pipefail
out=${1:-out/two_worlds}
dorado=${2:-build/apps/dorado}
shift $(( $# > 2 ? 2 : $# ))
[ "${1:-}" = "--" ] && shift
mkdir -p "$out"
"$dorado" bench configs/benchmark_fusion.yaml --out "$out/builtin"
/usr/bin/python3 benchmarks/mapping/fusion_table.py "$out/builtin"
xsim_args=(--out "$out/xsim" --dorado "$dorado" --seeds 100,101,102)
if [ $# -gt 0 ]; then xsim_args+=(--map-args "$*"); fi
/usr/bin/python3 benchmarks/xsim/run_xsim.py "${xsim_args[@]}"

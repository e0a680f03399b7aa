#!/bin/bash
# Tests of workflow/Snakefile against the real engines (registered in ctest by CMakeLists.txt):
#   test_workflow.sh bench    DORADO WORK  `dorado bench` on tiny_benchmark.yaml (the reference)
#   test_workflow.sh local    DORADO WORK  the workflow with `snakemake --cores 2`: same results.csv
#   test_workflow.sh slurm    DORADO WORK  the workflow through sbatch on a single-node Slurm that
#                                          this test starts (test_cluster.sh) and stops: same
#   test_workflow.sh resume   DORADO WORK  a run killed mid-way is redone next time, nothing else
# results.csv is compared whole except its time_per_scan rows (wall-clock time, never equal).
# Exit 77 (ctest: skipped) when snakemake or Slurm is missing; scripts/setup installs them.
set -u
HERE=$(cd "$(dirname "$0")" && pwd)
SOURCE=$(cd "$HERE/../.." && pwd)
MODE=$1
DORADO=$2
WORK=$3
SNAKEFILE=$SOURCE/workflow/Snakefile

fail() { echo "FAIL: $*" >&2; exit 1; }
skip() { echo "SKIPPED: $*" >&2; exit 77; }
scores() { grep -v ',time_per_scan,' "$1"; }

need_snakemake() {
    command -v snakemake >/dev/null || skip "snakemake not installed (Debian package snakemake; scripts/setup)"
}

same_as_bench() {
    local reference=$WORK/bench/out/results.csv
    [ -f "$reference" ] || fail "no $reference: the test_workflow_bench fixture did not run"
    [ -f "$1/results.csv" ] || fail "the workflow wrote no $1/results.csv"
    diff <(scores "$reference") <(scores "$1/results.csv") ||
        fail "$1/results.csv differs from dorado bench's $reference"
    echo "$1/results.csv: $(scores "$1/results.csv" | wc -l) lines, identical to dorado bench's"
    grep -q "(association: interpolate" "$1/results.md" || fail "$1/results.md does not name the association"
}

run_bench() {
    rm -rf "$WORK/bench" && mkdir -p "$WORK/bench"
    "$DORADO" bench "$HERE/tiny_benchmark.yaml" --out "$WORK/bench/out" --jobs 2 --no-plot ||
        fail "dorado bench failed"
    [ "$(scores "$WORK/bench/out/results.csv" | wc -l)" -gt 100 ] || fail "results.csv too short"
}

run_local() {
    need_snakemake
    rm -rf "$WORK/local" && mkdir -p "$WORK/local" && cd "$WORK/local" || exit 1
    snakemake -s "$SNAKEFILE" --cores 2 --config bench="$HERE/tiny_benchmark.yaml" \
        out="$WORK/local/out" dorado="$DORADO" || fail "snakemake failed"
    same_as_bench "$WORK/local/out"
    [ -d "$WORK/local/out/plots" ] || fail "no plots/ (dorado bench --score-only makes them)"
}

run_slurm() {
    need_snakemake
    for p in sbatch slurmctld slurmd munged; do
        command -v $p >/dev/null || [ -x /usr/sbin/$p ] ||
            skip "$p not installed (Debian packages slurm-wlm, munge; scripts/setup)"
    done
    [ "$(id -u)" = 0 ] || skip "the test cluster's slurmd must run as root"
    rm -rf "$WORK/slurm" && mkdir -p "$WORK/slurm" && cd "$WORK/slurm" || exit 1
    trap '"$HERE/test_cluster.sh" stop "$WORK/slurm/cluster"' EXIT
    local env
    env=$("$HERE/test_cluster.sh" start "$WORK/slurm/cluster") || fail "the test cluster did not start"
    eval "$env"
    snakemake -s "$SNAKEFILE" --profile "$SOURCE/workflow/profiles/slurm" \
        --config bench="$HERE/tiny_benchmark.yaml" out="$WORK/slurm/out" dorado="$DORADO" ||
        fail "snakemake on Slurm failed"
    # Every run and the report went through sbatch: one Slurm output file per job.
    local jobs
    jobs=$(ls .snakemake/slurm-*.out | wc -l)
    [ "$jobs" -eq 13 ] || fail "expected 13 Slurm jobs (2 simulations, 10 runs, the report), saw $jobs"
    echo "$jobs Slurm jobs"
    same_as_bench "$WORK/slurm/out"
}

# The pid of the process whose command line contains $1 (no process names: an exact argument).
# One grep over every /proc/PID/cmdline (NUL-separated arguments as lines, -z), not two processes
# per PID: polled every 0.2 s, that loop forked ~600 processes a time and was most of the
# test's system time.
pid_with_argument() {
    local match
    # The pattern comes from a file so that grep's own command line does not match it.
    match=$(grep -lzxF -f <(printf '%s\n' "$1") /proc/[0-9]*/cmdline 2>/dev/null | head -n 1)
    [ -n "$match" ] && { match=${match#/proc/}; echo "${match%/cmdline}"; }
}

run_resume() {
    need_snakemake
    rm -rf "$WORK/resume" && mkdir -p "$WORK/resume" && cd "$WORK/resume" || exit 1
    local out=$WORK/resume/out victim=$WORK/resume/out/runs/s04/map_constvel
    local args=(-s "$SNAKEFILE" --cores 1 --keep-going --config
        bench="$HERE/resume_benchmark.yaml" out="$out" dorado="$DORADO")
    snakemake "${args[@]}" >first.log 2>&1 &
    local smk=$! pid=""
    for _ in $(seq 1 600); do
        pid=$(pid_with_argument "$victim.tmp")
        [ -n "$pid" ] && break
        kill -0 $smk 2>/dev/null || fail "the workflow ended before $victim started (first.log)"
        sleep 0.2
    done
    [ -n "$pid" ] || fail "$victim never started"
    # The mapper takes ~5 ms per scan: 30 s of data (450 scans) leave it running for seconds.
    sleep 0.3
    kill -KILL "$pid" || fail "the run $victim ended before it could be killed"
    echo "killed the run $victim mid-way (pid $pid)"
    wait $smk && fail "the first invocation succeeded although a run was killed"
    [ -f "$victim/summary.json" ] && fail "the killed run looks finished"
    # Markers of what the first invocation finished, with their modification times.
    local before
    before=$(find "$out" -name summary.json -o -name simulation.json | sort | xargs stat -c '%n %Y.%y')
    [ -n "$before" ] || fail "the first invocation finished nothing"
    snakemake "${args[@]}" >second.log 2>&1 || fail "the second invocation failed (second.log)"
    [ -f "$victim/summary.json" ] || fail "the killed run was not redone"
    local after
    after=$(echo "$before" | cut -d' ' -f1 | xargs stat -c '%n %Y.%y')
    [ "$before" = "$after" ] || fail "runs finished by the first invocation were redone:
$(diff <(echo "$before") <(echo "$after"))"
    local redone
    redone=$(grep -cE '^(rule|localrule) (simulate|odometry|map):' second.log)
    local missing=$(( $(grep -c '"name"' <("$DORADO" bench "$HERE/resume_benchmark.yaml" --out "$out" --plan-only)) - $(echo "$before" | wc -l) ))
    [ "$redone" -eq "$missing" ] || fail "the second invocation ran $redone runs, $missing were missing"
    echo "second invocation: $redone of the runs (the killed one and any not started), none of the $(echo "$before" | wc -l) finished"
}

case "$MODE" in
bench) run_bench ;;
local) run_local ;;
slurm) run_slurm ;;
resume) run_resume ;;
*) fail "unknown mode $MODE" ;;
esac

#!/bin/bash
# A throw-away single-node Slurm cluster on localhost for the workflow tests (and for trying the
# Slurm profile by hand): munged with its own key and socket, slurmctld and slurmd from one
# generated slurm.conf, all state under DIR. Needs root (slurmd runs jobs as root here).
#
#   tests/workflow/test_cluster.sh start DIR   # prints "export SLURM_CONF=DIR/slurm.conf"
#   tests/workflow/test_cluster.sh stop DIR    # stops the three daemons started in DIR
#
# Exit status of start: 0 up (the node is idle), 2 a program is missing, 1 a daemon did not start
# (its log is printed).
set -u

die() { echo "test_cluster: $*" >&2; exit 1; }

start() {
    local dir=$1
    for p in munged mungekey slurmctld slurmd sinfo sbatch; do
        command -v "$p" >/dev/null || PATH=$PATH:/usr/sbin command -v "$p" >/dev/null ||
            { echo "test_cluster: $p not found (Debian packages munge, slurm-wlm)" >&2; exit 2; }
    done
    export PATH=$PATH:/usr/sbin
    [ "$(id -u)" = 0 ] || { echo "test_cluster: must run as root" >&2; exit 2; }
    mkdir -p "$dir"/{state,spool,munge}
    dir=$(cd "$dir" && pwd)
    chmod 700 "$dir/munge"
    # Ports from the directory's name, so two clusters on one machine do not collide.
    local base=$(( 20000 + $(echo "$dir" | cksum | cut -d' ' -f1) % 20000 ))
    local cpus mem
    cpus=$(nproc)
    mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
    [ -f "$dir/munge/munge.key" ] || mungekey -c -k "$dir/munge/munge.key" >/dev/null 2>&1 ||
        { dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 2>/dev/null; }
    chmod 400 "$dir/munge/munge.key"
    munged -f --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.sock" \
        --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" \
        --seed-file="$dir/munge/munged.seed" ||
        { cat "$dir/munge/munged.log" >&2; die "munged did not start"; }
    cat >"$dir/slurm.conf" <<CONF
ClusterName=dorado_test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$base
SlurmdPort=$((base + 1))
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.sock
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SlurmdParameters=config_overrides
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MinJobAge=300
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=dorado Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
    export SLURM_CONF=$dir/slurm.conf
    slurmctld -c -f "$SLURM_CONF" || { cat "$dir/slurmctld.log" >&2; die "slurmctld did not start"; }
    slurmd -N localhost -f "$SLURM_CONF" || { cat "$dir/slurmd.log" >&2; die "slurmd did not start"; }
    for _ in $(seq 1 60); do
        if sinfo -h -N -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
            echo "export SLURM_CONF=$SLURM_CONF"
            return 0
        fi
        sleep 0.5
    done
    echo "test_cluster: the node did not become idle:" >&2
    sinfo -N -l >&2 || true
    tail -n 20 "$dir/slurmctld.log" "$dir/slurmd.log" >&2
    exit 1
}

# Stops each daemon by the pid in its pid file (never by name), waiting for it to exit.
stop_pid_file() {
    local file=$1 pid
    [ -f "$file" ] || return 0
    pid=$(cat "$file")
    if [ -n "$pid" ] && kill "$pid" 2>/dev/null; then
        for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
        kill -9 "$pid" 2>/dev/null || true
    fi
    rm -f "$file"
}

stop() {
    local dir=$1
    stop_pid_file "$dir/slurmd.pid"
    stop_pid_file "$dir/slurmctld.pid"
    stop_pid_file "$dir/munge/munged.pid"
}

case "${1:-}" in
start) start "${2:?DIR}" ;;
stop) stop "${2:?DIR}" ;;
*) echo "usage: $0 start|stop DIR" >&2; exit 2 ;;
esac

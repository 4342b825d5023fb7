#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for checking the array jobs here
# (CI does): `local-cluster.sh start DIR` writes DIR/slurm.conf, starts
# slurmctld and slurmd with their state, spool and logs under DIR, and waits
# until the node is idle; `local-cluster.sh stop DIR` stops both. Needs root
# and Debian's slurm-wlm (Slurm 22.05). Point the client commands at it with
# `export SLURM_CONF=DIR/slurm.conf`.
#
# Not for a real cluster: no authentication (auth/none), every job as root.
set -euo pipefail
action=${1:?usage: local-cluster.sh start|stop DIR}
dir=$(mkdir -p "${2:?usage: local-cluster.sh start|stop DIR}" && cd "$2" && pwd)
export SLURM_CONF=$dir/slurm.conf

stop() {
    for daemon in slurmd slurmctld; do
        if [ -s "$dir/$daemon.pid" ]; then
            kill "$(cat "$dir/$daemon.pid")" 2> /dev/null || true
        fi
    done
    # Wait for both to exit (at most 20 s), then make sure.
    for _ in $(seq 40); do
        alive=0
        for daemon in slurmd slurmctld; do
            if [ -s "$dir/$daemon.pid" ] && kill -0 "$(cat "$dir/$daemon.pid")" 2> /dev/null; then
                alive=1
            fi
        done
        [ "$alive" = 0 ] && break
        sleep 0.5
    done
    for daemon in slurmd slurmctld; do
        if [ -s "$dir/$daemon.pid" ]; then
            kill -9 "$(cat "$dir/$daemon.pid")" 2> /dev/null || true
            rm -f "$dir/$daemon.pid"
        fi
    done
}

case "$action" in
start)
    host=$(hostname -s)
    cpus=$(nproc)
    mkdir -p "$dir/state" "$dir/spool" "$dir/log"
    cat > "$SLURM_CONF" <<CONF
ClusterName=scasm-local
SlurmctldHost=$host
AuthType=auth/none
CredType=cred/none
ProctrackType=proctrack/linuxproc
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
SlurmUser=root
SlurmdUser=root
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldPort=16817
SlurmdPort=16818
ReturnToService=2
MpiDefault=none
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MinJobAge=600
NodeName=$host CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
    slurmctld -f "$SLURM_CONF"
    slurmd -f "$SLURM_CONF"
    for _ in $(seq 60); do
        state=$(sinfo -h -o %T 2> /dev/null || true)
        if [ "$state" = idle ]; then
            echo "one-node Slurm up: node $host, $cpus CPUs, SLURM_CONF=$SLURM_CONF"
            exit 0
        fi
        sleep 0.5
    done
    echo "the node did not become idle in 30 s (state: ${state:-none}); logs in $dir/log" >&2
    tail -n 20 "$dir/log/slurmctld.log" "$dir/log/slurmd.log" >&2 || true
    stop
    exit 1
    ;;
stop)
    stop
    echo "one-node Slurm stopped"
    ;;
*)
    echo "usage: local-cluster.sh start|stop DIR" >&2
    exit 2
    ;;
esac

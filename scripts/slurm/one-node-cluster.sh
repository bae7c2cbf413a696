# shellcheck shell=bash
# A throwaway one-node Slurm cluster on localhost, for tests. Source this file, then
#
#   cluster_up DIR      # munged, slurmctld and slurmd with everything under DIR; exports SLURM_CONF
#   …                   # sbatch, squeue, scontrol, sinfo now talk to this cluster
#   cluster_down        # cancels its jobs, stops the three daemons (call it from an EXIT trap)
#
# Nothing is read from or written to /etc/slurm, /etc/munge or /run: the munge key, socket,
# slurm.conf, state, spool and logs live in DIR, and both Slurm ports are picked free, so a
# system Slurm on the same machine is neither used nor disturbed. The daemons run in the
# foreground as children of this shell (their PIDs are kept and only they are stopped). The
# node is described by `slurmd -C` (its CPUs, sockets, cores), scheduled by core without
# cgroups (proctrack/linuxproc, task/none), so it runs in a container without systemd.
# Needs root: slurmd starts every job as its user. Needs munge, slurmctld, slurmd, python3.

cluster_pids=()
cluster_dir=
cluster_node=

cluster_log() { echo "one-node-cluster: $*" >&2; }

# Runs a daemon in the foreground, in the background of this shell. With util-linux's
# setpriv it gets SIGTERM if this shell dies, even by SIGKILL, when no trap can run.
cluster_spawn() {
    local log=$1
    shift
    if command -v setpriv >/dev/null 2>&1; then
        setpriv --pdeathsig TERM -- "$@" 2>"$log" &
    else
        "$@" 2>"$log" &
    fi
    cluster_pids+=($!)
}

# Two free TCP ports on localhost, for slurmctld and slurmd.
cluster_free_ports() {
    python3 -c '
import socket
socks = [socket.socket() for _ in range(2)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(" ".join(str(s.getsockname()[1]) for s in socks))'
}

cluster_write_conf() {
    local dir=$1 node=$2 ctld_port=$3 slurmd_port=$4 hw
    # `slurmd -C` prints the node line as Slurm sees the hardware; memory is not scheduled.
    hw=$(slurmd -C | head -n 1 | sed -e 's/^NodeName=[^ ]* //' -e 's/ RealMemory=[0-9]*//')
    cat >"$dir/slurm.conf" <<CONF
ClusterName=beamflow-test
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool/%n
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MinJobAge=3600
NodeName=$node NodeAddr=127.0.0.1 $hw State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
}

# Polls `$@` once a second until it succeeds; after `timeout` seconds returns 1.
cluster_wait_for() {
    local timeout=$1
    shift
    local t
    for ((t = 0; t < timeout; t++)); do
        "$@" && return 0
        sleep 1
    done
    return 1
}

cluster_node_idle() { [ "$(sinfo -h -n "$cluster_node" -o %T 2>/dev/null)" = idle ]; }

cluster_munge_works() {
    munge -n -S "$cluster_dir/munge/munge.socket" 2>/dev/null |
        unmunge -S "$cluster_dir/munge/munge.socket" >/dev/null 2>&1
}

# Prints the last lines of every daemon's log (its stderr if it has no log file).
cluster_show_logs() {
    local f
    for f in "$cluster_dir"/log/*; do
        [ -s "$f" ] || continue
        [[ $f == *.stderr && -s ${f%.stderr}.log ]] && continue
        echo "----- $f (last 30 lines)" >&2
        tail -n 30 "$f" >&2
    done
}

cluster_up() {
    cluster_dir=$1
    cluster_node=$(hostname -s)
    local ports
    ports=$(cluster_free_ports)
    mkdir -p "$cluster_dir/munge" "$cluster_dir/state" "$cluster_dir/spool" "$cluster_dir/log"
    # munged wants its socket's directory (and those above, not made here) searchable by all.
    chmod 755 "$cluster_dir" "$cluster_dir/munge"

    mungekey --create --keyfile="$cluster_dir/munge/munge.key" || return 1
    cluster_spawn "$cluster_dir/log/munged.log" munged --foreground \
        --key-file="$cluster_dir/munge/munge.key" --socket="$cluster_dir/munge/munge.socket" \
        --pid-file="$cluster_dir/munge/munged.pid" --seed-file="$cluster_dir/munge/munged.seed"
    if ! cluster_wait_for 10 cluster_munge_works; then
        cluster_log "munged does not answer on $cluster_dir/munge/munge.socket"
        cluster_show_logs
        return 1
    fi

    # shellcheck disable=SC2086
    cluster_write_conf "$cluster_dir" "$cluster_node" $ports
    export SLURM_CONF=$cluster_dir/slurm.conf
    # In the foreground the daemons also log to stderr: kept apart, for errors met before
    # their log files are open.
    cluster_spawn "$cluster_dir/log/slurmctld.stderr" slurmctld -D -f "$SLURM_CONF"
    cluster_spawn "$cluster_dir/log/slurmd.stderr" slurmd -D -f "$SLURM_CONF" -N "$cluster_node"
    if ! cluster_wait_for 60 cluster_node_idle; then
        cluster_log "node $cluster_node not idle after 60 s:" \
            "$(sinfo -h -N -o '%N %T %E' 2>&1 || true)"
        cluster_show_logs
        return 1
    fi
    cluster_log "node $cluster_node idle (ports $ports, $cluster_dir)"
}

cluster_queue_empty() { [ -z "$(squeue -h -o %i 2>/dev/null)" ]; }

# True once `pid` has ended (gone, or a zombie waiting for `wait`).
cluster_exited() {
    [ ! -e "/proc/$1" ] || [ "$(awk '{print $3}' "/proc/$1/stat" 2>/dev/null)" = Z ]
}

# Alive daemons among the ones cluster_up started.
cluster_alive() {
    local pid alive=()
    for pid in "${cluster_pids[@]}"; do
        cluster_exited "$pid" || alive+=("$pid")
    done
    echo "${alive[*]}"
}

cluster_down() {
    [ ${#cluster_pids[@]} -gt 0 ] || return 0
    if [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
        # Jobs still queued or running (a failed test): cancel them, so that no job
        # outlives its slurmd. Every job on this private cluster is the caller's.
        scancel --partition=test 2>/dev/null || true
        cluster_wait_for 15 cluster_queue_empty || cluster_log "jobs left: $(squeue -h 2>&1)"
    fi
    # Stop in reverse order: slurmd, slurmctld, munged.
    local i pid
    for ((i = ${#cluster_pids[@]} - 1; i >= 0; i--)); do
        pid=${cluster_pids[i]}
        kill -TERM "$pid" 2>/dev/null || continue
        cluster_wait_for 15 cluster_exited "$pid" || kill -KILL "$pid" 2>/dev/null || true
        wait "$pid" 2>/dev/null || true
    done
    local left
    left=$(cluster_alive)
    cluster_pids=()
    if [ -n "$left" ]; then
        cluster_log "daemons still alive after SIGKILL: $left"
        return 1
    fi
}

#!/usr/bin/env bash
# cluster.sh — a throw-away, single-node Slurm cluster for testing demsweep.
#
# Everything (munge key/socket, slurm.conf, spool, state, logs, pids) lives
# under a caller-supplied STATE_DIR, so nothing global is touched apart from
# installing the Debian packages.  The daemons run as root (SlurmUser=root);
# munged runs as the `munge` user created by the Debian package.
#
# Usage:
#   cluster.sh install            install slurm-wlm + munge (root, apt-get)
#   cluster.sh start  STATE_DIR   start munged, slurmctld, slurmd; wait for idle
#   cluster.sh stop   STATE_DIR   stop exactly the daemons recorded in STATE_DIR/pids
#   cluster.sh status STATE_DIR   print sinfo / squeue
#
# After `start`, `source STATE_DIR/env.sh` so sbatch/squeue/sinfo/scontrol
# find the config (it exports SLURM_CONF).
#
# Exit codes: 0 ok, 1 runtime failure, 2 usage error,
#             3 cannot provide a cluster here (not root / no apt / no packages).
set -euo pipefail

# The daemons (slurmctld, slurmd, munged) live in /usr/sbin, which is often
# missing from non-root or CI PATHs.
PATH=$PATH:/usr/sbin:/sbin

readonly PROG=${0##*/}
readonly START_TIMEOUT=${CLUSTER_START_TIMEOUT:-60}   # seconds to wait for idle
readonly PARTITION=debug

die()  { local code=$1; shift; echo "$PROG: error: $*" >&2; exit "$code"; }
note() { echo "$PROG: $*"; }
usage() {
    sed -n '9,14p' "$0" | sed 's/^# \{0,1\}//' >&2
    exit 2
}

# True if PID is a live (non-zombie) process.
alive() {
    local pid=$1 st
    kill -0 "$pid" 2>/dev/null || return 1
    st=$(awk '{print $3}' "/proc/$pid/stat" 2>/dev/null) || return 1
    [[ $st != Z ]]
}

# True if PID's command line mentions DIR, i.e. it is one of our daemons
# (every daemon we start gets paths under STATE_DIR on its command line).
# Guards against killing an unrelated process that reused a recorded PID.
ours() {
    local pid=$1 dir=$2
    tr '\0' ' ' <"/proc/$pid/cmdline" 2>/dev/null | grep -qF -- "$dir/"
}

# ---------------------------------------------------------------- install ---
require_root() {
    [[ $EUID -eq 0 ]] || die 3 "must run as root (daemons run as root/munge); cannot provide a cluster here"
}

have_slurm() {
    command -v slurmctld >/dev/null && command -v slurmd >/dev/null \
        && command -v munged >/dev/null && command -v sbatch >/dev/null
}

cmd_install() {
    if have_slurm; then
        return 0
    fi
    require_root
    command -v apt-get >/dev/null || die 3 "slurmctld not found and apt-get is unavailable; cannot provide a cluster here"
    local log
    log=$(mktemp /tmp/cluster-install.XXXXXX.log)
    note "installing slurm-wlm + munge via apt-get (log: $log)"
    if ! { DEBIAN_FRONTEND=noninteractive apt-get update -q \
           && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends \
                  -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold \
                  slurm-wlm munge; } >"$log" 2>&1; then
        tail -n 30 "$log" >&2
        die 3 "apt-get install slurm-wlm munge failed (full log: $log); cannot provide a cluster here"
    fi
    have_slurm || die 3 "packages installed but slurmctld/slurmd/munged/sbatch still not on PATH"
    rm -f "$log"
}

# ------------------------------------------------------------------ start ---
# Print the tail of every log in STATE_DIR (used on failure).
dump_logs() {
    local state=$1 f
    for f in "$state"/log/*.log; do
        [[ -e $f ]] || continue
        echo "----- tail of $f -----" >&2
        tail -n 25 "$f" >&2
    done
}

# Read a pid file written by a daemon, waiting briefly for it to appear.
wait_pidfile() {
    local file=$1 i
    for ((i = 0; i < 50; i++)); do
        if [[ -s $file ]]; then
            cat "$file"
            return 0
        fi
        sleep 0.1
    done
    return 1
}

# record_pid NAME PID: append "NAME PID" to STATE/pids (read back by stop).
record_pid() { echo "$1 $2" >>"$STATE/pids"; }

start_munge() {
    local key=$STATE/munge/munge.key
    # 0755: clients (slurm daemons, sbatch by any user) must reach the socket.
    install -d -o munge -g munge -m 0755 "$STATE/munge"
    dd if=/dev/urandom of="$key" bs=1 count=1024 status=none
    chown munge:munge "$key"
    chmod 0400 "$key"
    # munged refuses insecure (group/other-writable) parent directories;
    # --force turns those checks into warnings so any STATE_DIR works.
    runuser -u munge -- munged --force \
        --key-file="$key" \
        --socket="$STATE/munge/munge.socket" \
        --pid-file="$STATE/munge/munged.pid" \
        --log-file="$STATE/log/munged.log" \
        --seed-file="$STATE/munge/munged.seed" \
        || { dump_logs "$STATE"; die 1 "munged failed to start"; }
    local pid
    pid=$(wait_pidfile "$STATE/munge/munged.pid") \
        || { dump_logs "$STATE"; die 1 "munged did not write its pid file"; }
    alive "$pid" || { dump_logs "$STATE"; die 1 "munged exited right after start"; }
    record_pid munged "$pid"
}

# True if something listens on TCP PORT on this host.
port_busy() { (exec 3<>"/dev/tcp/127.0.0.1/$1") 2>/dev/null; }

# Pick SlurmctldPort/SlurmdPort: 6817/6818 unless taken (e.g. by a system
# Slurm or another test cluster), then the next free pair.  Override with
# CLUSTER_CTLD_PORT / CLUSTER_SLURMD_PORT.
pick_ports() {
    if [[ -n ${CLUSTER_CTLD_PORT:-} || -n ${CLUSTER_SLURMD_PORT:-} ]]; then
        CTLD_PORT=${CLUSTER_CTLD_PORT:-6817}
        SLURMD_PORT=${CLUSTER_SLURMD_PORT:-6818}
        return 0
    fi
    local p
    for ((p = 6817; p < 6917; p += 2)); do
        if ! port_busy "$p" && ! port_busy $((p + 1)); then
            CTLD_PORT=$p
            SLURMD_PORT=$((p + 1))
            return 0
        fi
    done
    die 1 "no free port pair in 6817-6916 for slurmctld/slurmd"
}

write_slurm_conf() {
    local node cpus
    node=$(hostname -s)
    cpus=$(nproc)
    cat >"$STATE/slurm.conf" <<EOF
# Generated by $PROG for a local single-node test cluster.
# Addresses are pinned to 127.0.0.1 so the hostname need not resolve.
# batch_sched_delay=0/sched_min_interval=0: start jobs ~3 s sooner per wave.
ClusterName=demsweep-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$STATE/munge/munge.socket
SlurmctldPort=$CTLD_PORT
SlurmdPort=$SLURMD_PORT
StateSaveLocation=$STATE/ctld
SlurmdSpoolDir=$STATE/spool
SlurmctldPidFile=$STATE/run/slurmctld.pid
SlurmdPidFile=$STATE/run/slurmd.pid
SlurmctldLogFile=$STATE/log/slurmctld.log
SlurmdLogFile=$STATE/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SwitchType=switch/none
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmctldTimeout=30
SlurmdTimeout=30
MessageTimeout=10
InactiveLimit=0
KillWait=5
MinJobAge=300
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=$PARTITION Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF
    cat >"$STATE/env.sh" <<EOF
# source this to talk to the test cluster in $STATE
export SLURM_CONF=$STATE/slurm.conf
EOF
}

start_slurm() {
    local conf=$STATE/slurm.conf pid
    # -i: ignore (empty) saved state; daemons fork and write their pid files.
    slurmctld -f "$conf" -i \
        || { dump_logs "$STATE"; die 1 "slurmctld failed to start"; }
    pid=$(wait_pidfile "$STATE/run/slurmctld.pid") \
        || { dump_logs "$STATE"; die 1 "slurmctld did not write its pid file"; }
    alive "$pid" || { dump_logs "$STATE"; die 1 "slurmctld exited right after start"; }
    record_pid slurmctld "$pid"

    slurmd -f "$conf" \
        || { dump_logs "$STATE"; die 1 "slurmd failed to start"; }
    pid=$(wait_pidfile "$STATE/run/slurmd.pid") \
        || { dump_logs "$STATE"; die 1 "slurmd did not write its pid file"; }
    alive "$pid" || { dump_logs "$STATE"; die 1 "slurmd exited right after start"; }
    record_pid slurmd "$pid"
}

wait_idle() {
    local deadline=$((SECONDS + START_TIMEOUT)) state=""
    while ((SECONDS < deadline)); do
        state=$(SLURM_CONF=$STATE/slurm.conf sinfo -h -N -o '%T' 2>/dev/null | head -n1) || true
        case $state in
            idle*) return 0 ;;
        esac
        sleep 1
    done
    echo "last sinfo state: '${state:-<none>}'" >&2
    SLURM_CONF=$STATE/slurm.conf sinfo -N -l >&2 || true
    dump_logs "$STATE"
    die 1 "node did not become idle within ${START_TIMEOUT}s"
}

cmd_start() {
    require_root
    have_slurm || die 3 "slurm/munge not installed; run: $PROG install"
    mkdir -p "$1"
    STATE=$(cd "$1" && pwd -P)
    [[ $STATE != *[[:space:]]* ]] || die 2 "STATE_DIR must not contain whitespace (slurm.conf cannot quote it): '$STATE'"
    if [[ -s $STATE/pids ]] && pids_alive "$STATE"; then
        die 1 "a cluster recorded in $STATE/pids is still running; run: $PROG stop $STATE"
    fi
    # Fresh state every time (restartable): wipe what a previous run left.
    rm -rf "$STATE"/{munge,ctld,spool,run,log,slurm.conf,env.sh,pids}
    chmod 0755 "$STATE"   # munge user must traverse it to reach its socket dir
    mkdir -p "$STATE"/{ctld,spool,run,log}
    : >"$STATE/pids"
    chown munge:munge "$STATE/log"   # munged writes its log here
    chmod 0755 "$STATE/log"
    runuser -u munge -- test -w "$STATE/log" \
        || die 1 "the munge user cannot reach $STATE: make its parent directories world-traversable (chmod o+x)"

    # If anything below fails, stop whatever we already started.
    trap 'rc=$?; if ((rc != 0)); then echo "$PROG: start failed; stopping what was started" >&2; cmd_stop "$STATE" >&2 || true; fi' EXIT

    start_munge
    pick_ports
    write_slurm_conf
    start_slurm
    wait_idle
    trap - EXIT
    note "cluster up in $STATE (node $(hostname -s), $(nproc) CPUs); source $STATE/env.sh"
}

# ------------------------------------------------------------------- stop ---
# True if any pid recorded in STATE/pids is still a live process.
pids_alive() {
    local name pid
    while read -r name pid; do
        [[ -n ${pid:-} ]] && alive "$pid" && ours "$pid" "$1" && return 0
    done <"$1/pids"
    return 1
}

# Cancel every job of this cluster so no slurmstepd/job processes outlive
# slurmd (slurmstepd is deliberately independent of slurmd).
cancel_jobs() {
    local state=$1 i
    [[ -f $state/slurm.conf ]] || return 0
    export SLURM_CONF=$state/slurm.conf
    [[ -n $(squeue -h -o %A 2>/dev/null) ]] || return 0
    scancel --full --partition="$PARTITION" 2>/dev/null || return 0
    for ((i = 0; i < 20; i++)); do            # up to 10 s
        [[ -z $(squeue -h -t running,completing -o %A 2>/dev/null) ]] && return 0
        sleep 0.5
    done
    echo "$PROG: warning: jobs still running/completing after scancel" >&2
}

# Send TERM to PID, wait up to 10 s, then KILL.
terminate() {
    local pid=$1 name=$2 i
    kill -TERM "$pid" 2>/dev/null || return 0
    for ((i = 0; i < 100; i++)); do
        alive "$pid" || return 0
        sleep 0.1
    done
    echo "$PROG: $name (pid $pid) ignored TERM, sending KILL" >&2
    kill -KILL "$pid" 2>/dev/null || true
}

cmd_stop() {
    local state=$1 name pid
    [[ -f $state/pids ]] || { note "no $state/pids; nothing to stop"; return 0; }
    state=$(cd "$state" && pwd -P)
    cancel_jobs "$state"
    # slurmd, then slurmctld, munged last (slurm talks to munge on shutdown).
    local want
    for want in slurmd slurmctld munged; do
        while read -r name pid; do
            [[ $name == "$want" && -n ${pid:-} ]] || continue
            if alive "$pid" && ours "$pid" "$state"; then
                terminate "$pid" "$name"
            fi
        done <"$state/pids"
    done
    rm -f "$state/pids"
    note "cluster in $state stopped"
}

# ----------------------------------------------------------------- status ---
cmd_status() {
    local state=$1
    [[ -f $state/slurm.conf ]] || die 1 "no cluster config in $state"
    export SLURM_CONF=$state/slurm.conf
    sinfo
    squeue
}

# ------------------------------------------------------------------- main ---
main() {
    [[ $# -ge 1 ]] || usage
    local cmd=$1; shift
    case $cmd in
        install) [[ $# -eq 0 ]] || usage; cmd_install ;;
        start)   [[ $# -eq 1 ]] || usage; cmd_start "$1" ;;
        stop)    [[ $# -eq 1 ]] || usage; cmd_stop "$1" ;;
        status)  [[ $# -eq 1 ]] || usage; cmd_status "$1" ;;
        -h|--help|help) usage ;;
        *) usage ;;
    esac
}

main "$@"

#!/usr/bin/env bash
# Start a one-node SLURM cluster (munged + slurmctld + slurmd) on this Debian 12 host.
#
# Idempotent: packages are installed only when missing, the config is rewritten (and
# the daemons restarted) only when it changed, and running daemons are reused.
# Needs root. Does not use systemd (CI containers have none as PID 1).
# See README.md beside this file. Stop with stop-cluster.sh.
#
# Environment knobs (all optional):
#   SLURM_CI_PARTITION   partition name                        (default: debug)
#   SLURM_CI_CPUS        CPUs to advertise for the node        (default: what `slurmd -C` finds)
#   SLURM_CI_TIMEOUT     seconds to wait for node / test job   (default: 60)
#   SLURM_CI_SKIP_TEST=1 skip the srun/sbatch smoke test
set -euo pipefail

PARTITION=${SLURM_CI_PARTITION:-debug}
TIMEOUT=${SLURM_CI_TIMEOUT:-60}
CONF_DIR=/etc/slurm
CONF=$CONF_DIR/slurm.conf
STATE_DIR=/var/lib/slurm/slurmctld
SPOOL_DIR=/var/lib/slurm/slurmd
LOG_DIR=/var/log/slurm
RUN_DIR=/run/slurm
MUNGE_KEY=/etc/munge/munge.key
MUNGE_PID=/run/munge/munged.pid
MUNGE_LOG=/var/log/munge/munged.log
MARKER="# written by .ci/slurm/start-cluster.sh"
T0=$(date +%s)

log() { printf '[start-cluster %3ss] %s\n' "$(($(date +%s) - T0))" "$*" >&2; }

diagnostics() {
  local f
  for f in "$LOG_DIR/slurmctld.log" "$LOG_DIR/slurmd.log" "$MUNGE_LOG" \
           "$RUN_DIR/slurmctld.stderr" "$RUN_DIR/slurmd.stderr" "$RUN_DIR/munged.stderr"; do
    if [[ -s $f ]]; then
      echo "----- tail -n 25 $f -----" >&2
      tail -n 25 "$f" >&2 || true
    fi
  done
  if command -v sinfo >/dev/null 2>&1; then
    echo "----- sinfo -----" >&2
    timeout 10 sinfo -N -l >&2 2>&1 || true
  fi
}

die() {
  echo "start-cluster.sh: ERROR: $*" >&2
  diagnostics
  exit 1
}

# pid_alive PIDFILE NAME: true when the pid file names a live process called NAME.
pid_alive() {
  local pid
  [[ -s $1 ]] || return 1
  pid=$(<"$1")
  [[ $pid =~ ^[0-9]+$ ]] || return 1
  [[ -r /proc/$pid/comm && $(</proc/"$pid"/comm) == "$2" ]]
}

[[ $(id -u) -eq 0 ]] || die "must run as root (it installs packages and starts daemons)"

# ---------------------------------------------------------------- packages
pkg_installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q 'install ok installed'; }

install_packages() {
  local missing=() p
  for p in munge slurmctld slurmd slurm-client; do
    pkg_installed "$p" || missing+=("$p")
  done
  ((${#missing[@]})) || return 0
  log "installing Debian packages (missing: ${missing[*]})"
  export DEBIAN_FRONTEND=noninteractive
  # The maintainer scripts would try to start munge/slurm services; we start them
  # ourselves, so forbid that for the duration of the install (policy-rc.d, exit 101).
  local policy=/usr/sbin/policy-rc.d created_policy=0
  if [[ ! -e $policy ]]; then
    printf '#!/bin/sh\nexit 101\n' >"$policy"
    chmod 755 "$policy"
    created_policy=1
  fi
  local apt_opts=(-y -q --no-install-recommends -o Dpkg::Options::=--force-confdef -o Dpkg::Options::=--force-confold)
  local ok=0
  # Update the package lists only when needed: when they are absent or the install fails
  # (e.g. stale lists pointing at files the mirror no longer has).
  if apt-cache show slurmd >/dev/null 2>&1 && apt-cache show munge >/dev/null 2>&1; then
    apt-get install "${apt_opts[@]}" slurm-wlm munge >/tmp/start-cluster-apt.log 2>&1 && ok=1
  fi
  if ((!ok)); then
    log "running apt-get update"
    apt-get update -q >>/tmp/start-cluster-apt.log 2>&1 || true
    apt-get install "${apt_opts[@]}" slurm-wlm munge >>/tmp/start-cluster-apt.log 2>&1 && ok=1
  fi
  ((created_policy)) && rm -f "$policy"
  if ((!ok)); then
    tail -n 30 /tmp/start-cluster-apt.log >&2
    die "cannot install packages slurm-wlm munge with apt-get (log: /tmp/start-cluster-apt.log)"
  fi
  log "packages installed: $(dpkg-query -W -f='${Package}=${Version} ' slurmd slurmctld munge)"
}

install_packages
for c in munged slurmctld slurmd sbatch srun squeue sinfo scontrol; do
  command -v "$c" >/dev/null 2>&1 || die "command '$c' missing although its package is installed"
done

# ---------------------------------------------------------------- munge
start_munge() {
  getent passwd munge >/dev/null || die "cannot start munged: user 'munge' does not exist (package munge broken?)"
  install -d -m 0700 -o munge -g munge /etc/munge /var/lib/munge /var/log/munge
  install -d -m 0755 -o munge -g munge /run/munge
  if [[ ! -s $MUNGE_KEY ]]; then
    log "creating munge key $MUNGE_KEY"
    if command -v mungekey >/dev/null 2>&1; then
      mungekey --create --keyfile="$MUNGE_KEY" --force
    else
      dd if=/dev/urandom of="$MUNGE_KEY" bs=1 count=1024 status=none
    fi
  fi
  chown munge:munge "$MUNGE_KEY"
  chmod 0400 "$MUNGE_KEY"
  if munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
    # Running already (ours, or one started by the package or an earlier session).
    log "munged already running${MUNGE_PID:+ (pid $(cat "$MUNGE_PID" 2>/dev/null || echo '?'))}"
  else
    log "starting munged"
    rm -f "$MUNGE_PID"
    # munged daemonizes itself; run it as the munge user (it refuses root without --force).
    runuser -u munge -- /usr/sbin/munged --pid-file="$MUNGE_PID" >"$RUN_DIR/munged.stderr" 2>&1 ||
      die "cannot start munged: $(tail -n 3 "$RUN_DIR/munged.stderr" | tr '\n' ' ')"
  fi
  local i
  for ((i = 0; i < 50; i++)); do
    munge -n 2>/dev/null | unmunge >/dev/null 2>&1 && return 0
    sleep 0.2
  done
  die "cannot start munged: 'munge -n | unmunge' still fails after 10 s"
}

# ---------------------------------------------------------------- config
HOST=$(hostname -s)
[[ -n $HOST ]] || die "empty hostname"

write_config() {
  # slurmd -C prints this host's real topology, e.g.
  # NodeName=vm CPUs=2 Boards=1 SocketsPerBoard=1 CoresPerSocket=2 ThreadsPerCore=1 RealMemory=24105
  local detected cpus sockets cores threads mem extra=""
  detected=$(slurmd -C 2>/dev/null | head -n 1) || true
  [[ $detected == NodeName=* ]] || die "cannot start slurmd: 'slurmd -C' gave no node line ($(slurmd -C 2>&1 | head -n 3 | tr '\n' ' '))"
  cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<<"$detected")
  sockets=$(sed -n 's/.* SocketsPerBoard=\([0-9]*\).*/\1/p' <<<"$detected")
  cores=$(sed -n 's/.* CoresPerSocket=\([0-9]*\).*/\1/p' <<<"$detected")
  threads=$(sed -n 's/.* ThreadsPerCore=\([0-9]*\).*/\1/p' <<<"$detected")
  mem=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<<"$detected")
  [[ -n $cpus && -n $sockets && -n $cores && -n $threads && -n $mem ]] ||
    die "cannot parse 'slurmd -C' output: $detected"
  mem=$((mem * 9 / 10))   # a bit below the real memory, or slurmctld drains the node
  local node="NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$cpus SocketsPerBoard=$sockets CoresPerSocket=$cores ThreadsPerCore=$threads RealMemory=$mem State=UNKNOWN"
  if [[ -n ${SLURM_CI_CPUS:-} && $SLURM_CI_CPUS != "$cpus" ]]; then
    # Advertise more (or fewer) CPUs than the hardware has; slurmd must be told to trust the config.
    node="NodeName=$HOST NodeAddr=127.0.0.1 CPUs=$SLURM_CI_CPUS RealMemory=$mem State=UNKNOWN"
    extra="SlurmdParameters=config_overrides"
  fi
  cat <<EOF
$MARKER -- do not edit, it is regenerated.
ClusterName=ci
SlurmctldHost=$HOST(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
MpiDefault=none
MailProg=/bin/true
ReturnToService=2
StateSaveLocation=$STATE_DIR
SlurmdSpoolDir=$SPOOL_DIR
SlurmctldPidFile=$RUN_DIR/slurmctld.pid
SlurmdPidFile=$RUN_DIR/slurmd.pid
SlurmctldLogFile=$LOG_DIR/slurmctld.log
SlurmdLogFile=$LOG_DIR/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
# No cgroups (containers / VMs without a cgroup hierarchy slurm can use).
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
PropagateResourceLimits=NONE
# No accounting database: sacct/sacctmgr do not work; keep finished jobs in slurmctld's
# memory for a day so "squeue --states=all" and "scontrol show job" still report them.
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MinJobAge=86400
MaxJobCount=100000
# Fast scheduling and failure detection.
SchedulerType=sched/builtin
SchedulerParameters=sched_interval=2,sched_min_interval=0,batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SlurmctldTimeout=10
SlurmdTimeout=30
MessageTimeout=10
InactiveLimit=0
# Reject at submission (instead of leaving PENDING forever) jobs that cannot fit the node.
EnforcePartLimits=ALL
KillWait=5
Waittime=0
$extra
$node
PartitionName=$PARTITION Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
}

# ---------------------------------------------------------------- daemons
stop_daemon() { # NAME PIDFILE
  local pid i
  pid_alive "$2" "$1" || return 0
  pid=$(<"$2")
  kill "$pid" 2>/dev/null || true
  for ((i = 0; i < 50; i++)); do
    [[ -d /proc/$pid ]] || return 0
    sleep 0.2
  done
  kill -9 "$pid" 2>/dev/null || true
}

start_daemon() { # NAME ARGS...
  local name=$1 i
  shift
  log "starting $name"
  : >"$RUN_DIR/$name.stderr"
  "$name" "$@" >"$RUN_DIR/$name.stderr" 2>&1 ||
    die "cannot start $name: it exited with status $? ($(tail -n 3 "$RUN_DIR/$name.stderr" | tr '\n' ' '))"
  for ((i = 0; i < 50; i++)); do
    pid_alive "$RUN_DIR/$name.pid" "$name" && return 0
    sleep 0.2
  done
  die "cannot start $name: no live process after 10 s; last error in its log: $(last_error "$LOG_DIR/$name.log")"
}

# last_error LOGFILE: the last error/fatal line of a slurm log, minus the harmless PMIx noise.
last_error() {
  tail -n 40 "$1" 2>/dev/null | grep -E 'error:|fatal:' | grep -viE 'pmix|MPI' | tail -n 1 |
    sed 's/^\[[^]]*\] //' || true
}

install -d -m 0755 "$CONF_DIR" "$RUN_DIR" "$LOG_DIR" /var/lib/slurm
install -d -m 0700 "$STATE_DIR"
install -d -m 0755 "$SPOOL_DIR"

start_munge

NEW_CONF=$(write_config)
restart=0
if [[ ! -f $CONF ]] || [[ $(<"$CONF") != "$NEW_CONF" ]]; then
  if [[ -f $CONF ]] && ! grep -qF "$MARKER" "$CONF"; then
    log "keeping a copy of the foreign $CONF as $CONF.before-ci"
    cp -p "$CONF" "$CONF.before-ci"
  fi
  printf '%s\n' "$NEW_CONF" >"$CONF"
  chmod 0644 "$CONF"
  restart=1
  log "wrote $CONF"
fi

if ((restart)); then
  stop_daemon slurmd "$RUN_DIR/slurmd.pid"
  stop_daemon slurmctld "$RUN_DIR/slurmctld.pid"
fi

if pid_alive "$RUN_DIR/slurmctld.pid" slurmctld; then
  log "slurmctld already running (pid $(<"$RUN_DIR/slurmctld.pid"))"
else
  # -c: start from a clean state (no jobs or node states left from an earlier run).
  start_daemon slurmctld -c
fi
for ((i = 0; ; i++)); do
  timeout 5 scontrol ping 2>/dev/null | grep -q 'is UP' && break
  ((i < TIMEOUT * 2)) || die "cannot start slurmctld: 'scontrol ping' does not answer UP after ${TIMEOUT} s ($(last_error "$LOG_DIR/slurmctld.log"))"
  sleep 0.5
done

if pid_alive "$RUN_DIR/slurmd.pid" slurmd; then
  log "slurmd already running (pid $(<"$RUN_DIR/slurmd.pid"))"
else
  start_daemon slurmd
fi

# ---------------------------------------------------------------- wait for the node
state=""
for ((i = 0; ; i++)); do
  state=$(timeout 5 sinfo -h -n "$HOST" -o %T 2>/dev/null | head -n 1 || true)
  case $state in
    idle | mixed | allocated | completing) break ;;
    down* | drain* | fail*)
      # A node left down by an earlier run (or flagged before slurmd registered): resume it.
      scontrol update NodeName="$HOST" State=RESUME >/dev/null 2>&1 || true ;;
  esac
  ((i < TIMEOUT * 2)) || die "cannot start slurmd: node $HOST is '${state:-unknown}', not idle, after ${TIMEOUT} s ($(last_error "$LOG_DIR/slurmd.log"))"
  sleep 0.5
done
log "node $HOST is $state"

# ---------------------------------------------------------------- smoke test
if [[ ${SLURM_CI_SKIP_TEST:-0} != 1 ]]; then
  out=$(timeout "$TIMEOUT" srun -N1 -n1 -t 1 hostname 2>&1) ||
    die "a test job does not run: 'srun hostname' failed: $out"
  log "srun hostname -> $out"
  jobid=$(sbatch --parsable -N1 -n1 -t 1 -D /tmp -o "$LOG_DIR/smoke-%j.out" --wrap 'srun -n1 hostname' 2>&1) ||
    die "a test job cannot be submitted: sbatch failed: $jobid"
  jobid=${jobid%%;*}
  for ((i = 0; ; i++)); do
    jstate=$(timeout 5 squeue -h -j "$jobid" --states=all -o %T 2>/dev/null || true)
    [[ $jstate == COMPLETED ]] && break
    case $jstate in
      FAILED | CANCELLED | TIMEOUT | NODE_FAIL | BOOT_FAIL | OUT_OF_MEMORY)
        die "the test batch job $jobid ended $jstate: $(cat "$LOG_DIR/smoke-$jobid.out" 2>/dev/null)" ;;
    esac
    ((i < TIMEOUT * 5)) || die "the test batch job $jobid is still '${jstate:-unknown}' after ${TIMEOUT} s"
    sleep 0.2
  done
  rm -f "$LOG_DIR/smoke-$jobid.out"
  log "sbatch test job $jobid COMPLETED"
fi

log "cluster is up: partition '$PARTITION', node $HOST ($(sinfo -h -n "$HOST" -o '%c CPUs, %m MB'))"
cat <<EOF
# SLURM one-node cluster is up (config $CONF, logs $LOG_DIR).
# No environment is needed: the client commands read $CONF.
# Run Snakemake with, e.g.:
#   snakemake --executor slurm --slurm-status-command squeue \\
#     --slurm-init-seconds-before-status-checks 1 \\
#     --default-resources slurm_partition=$PARTITION runtime=10 ...
# (--slurm-status-command squeue is required: there is no accounting database, and with
#  the default 'sacct' Snakemake loses track of its jobs and hangs; see README.md.)
SLURM_CONF=$CONF
EOF

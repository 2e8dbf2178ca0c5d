#!/usr/bin/env bash
# Stop the slurmd, slurmctld and munged started by start-cluster.sh (idempotent).
# Only the processes named in their pid files are signalled (checked by process name).
set -euo pipefail

RUN_DIR=/run/slurm

# stop NAME PIDFILE: SIGTERM, wait up to 10 s, then SIGKILL.
stop() {
  local name=$1 pidfile=$2 pid i
  if [[ ! -s $pidfile ]]; then
    echo "$name: not running (no $pidfile)"
    return 0
  fi
  pid=$(<"$pidfile")
  if [[ ! $pid =~ ^[0-9]+$ || ! -r /proc/$pid/comm || $(</proc/"$pid"/comm) != "$name" ]]; then
    echo "$name: not running (stale $pidfile)"
    rm -f "$pidfile"
    return 0
  fi
  kill "$pid" 2>/dev/null || true
  for ((i = 0; i < 50; i++)); do
    if [[ ! -d /proc/$pid ]]; then
      echo "$name: stopped (pid $pid)"
      rm -f "$pidfile"
      return 0
    fi
    sleep 0.2
  done
  kill -9 "$pid" 2>/dev/null || true
  echo "$name: killed (pid $pid did not stop within 10 s)"
  rm -f "$pidfile"
}

[[ $(id -u) -eq 0 ]] || { echo "stop-cluster.sh: must run as root" >&2; exit 1; }

stop slurmd "$RUN_DIR/slurmd.pid"
stop slurmctld "$RUN_DIR/slurmctld.pid"
stop munged /run/munge/munged.pid
if command -v scontrol >/dev/null 2>&1; then
  echo "note: the SLURM client stays installed, so every snakemake start now waits ~9 s for" \
    "'scontrol show config'; start the cluster again or 'apt-get remove slurm-client'" \
    "(README.md beside this script, 'A slower Snakemake start')"
fi

#!/usr/bin/env bash
# A real single-node Slurm cluster in a private directory, for testing campaigns end to end
# (tests/slurm.rs) — Debian's munge, slurmctld and slurmd, started by hand without systemd.
#
#   scripts/slurm-local.sh start DIR   # writes DIR/slurm.conf, starts munged, slurmctld, slurmd;
#                                      # prints the line to source (SLURM_CONF=DIR/slurm.conf)
#   scripts/slurm-local.sh stop DIR    # cancels this cluster's jobs, then stops exactly the
#                                      # daemons it started (by the PIDs saved in DIR)
#
# Needs root (slurmd runs jobs as their user) and the packages slurmctld slurmd slurm-client
# munge. Nothing outside DIR is written; the daemons listen on two free-looking ports on
# 127.0.0.1 chosen per start (SLURM_LOCAL_PORT overrides), so a real cluster's configuration and
# daemons on the machine are never touched.
set -euo pipefail

cmd=${1:-}
dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ]; then
  echo "usage: $0 start|stop DIR" >&2
  exit 2
fi

wait_for() { # seconds, command...: polls every 0.2 s until the command succeeds
  local n=$(($1 * 5))
  shift
  for _ in $(seq "$n"); do
    if "$@" >/dev/null 2>&1; then return 0; fi
    sleep 0.2
  done
  return 1
}

stop_pid() { # name: SIGTERM the PID in DIR/NAME.pid if it is still that daemon, then wait
  local f="$dir/$1.pid"
  [ -f "$f" ] || return 0
  local pid
  pid=$(cat "$f")
  if [ -n "$pid" ] && [ "$(cat "/proc/$pid/comm" 2>/dev/null)" = "$1" ]; then
    kill "$pid" 2>/dev/null || true
    wait_for 10 sh -c "! kill -0 $pid" || kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$f"
}

case "$cmd" in
start)
  for p in munged slurmctld slurmd sbatch scontrol; do
    command -v "$p" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin"
    command -v "$p" >/dev/null 2>&1 || { echo "slurm-local: $p not found (apt-get install slurmctld slurmd slurm-client munge)" >&2; exit 3; }
  done
  if [ "$(id -u)" -ne 0 ]; then
    echo "slurm-local: must run as root (slurmd starts jobs as their user)" >&2
    exit 3
  fi
  mkdir -p "$dir"
  dir=$(cd "$dir" && pwd)
  # munged refuses group- or world-writable directories on the way to its key and socket.
  chmod 700 "$dir"
  mkdir -p "$dir/munge" "$dir/state" "$dir/spool"
  chmod 700 "$dir/munge"
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 400 "$dir/munge/munge.key"
  munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munge/munged.log" \
    --seed-file="$dir/munge/munged.seed" --force
  wait_for 10 test -S "$dir/munge/munge.socket" || { echo "slurm-local: munged did not start ($dir/munge/munged.log)" >&2; exit 1; }

  port=${SLURM_LOCAL_PORT:-$((20000 + (RANDOM % 10000) * 2))}
  host=$(hostname -s)
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ { printf "%d", $2 / 1024 / 2 }' /proc/meminfo)
  cat >"$dir/slurm.conf" <<EOF
# Written by scripts/slurm-local.sh: a one-node test cluster private to $dir.
ClusterName=lorentz-local
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CryptoType=crypto/munge
MpiDefault=none
# No systemd, no cgroups: track job processes through /proc and bind no tasks.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
ReturnToService=2
# No slurmdbd (so no sacct): finished jobs stay readable with scontrol show job for an hour.
MinJobAge=3600
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  export SLURM_CONF="$dir/slurm.conf"
  # -i: ignore state from an earlier start in this directory.
  slurmctld -i
  wait_for 15 scontrol ping || { echo "slurm-local: slurmctld did not answer ($dir/slurmctld.log)" >&2; exit 1; }
  slurmd
  wait_for 30 sh -c "sinfo -h -N -o %t | grep -qx idle" || { echo "slurm-local: the node did not become idle ($dir/slurmd.log)" >&2; exit 1; }
  echo "export SLURM_CONF=$dir/slurm.conf"
  ;;
stop)
  [ -d "$dir" ] || exit 0
  dir=$(cd "$dir" && pwd)
  if [ -f "$dir/slurm.conf" ] && [ -f "$dir/slurmctld.pid" ]; then
    export SLURM_CONF="$dir/slurm.conf"
    # slurmstepd can outlive slurmd: cancel this cluster's jobs first and let their steps end.
    scancel --full --quiet "--user=$(id -un)" 2>/dev/null || true
    wait_for 10 sh -c '[ -z "$(squeue -h -o %i 2>/dev/null)" ]' || true
  fi
  stop_pid slurmd
  stop_pid slurmctld
  stop_pid munged
  ;;
*)
  echo "usage: $0 start|stop DIR" >&2
  exit 2
  ;;
esac

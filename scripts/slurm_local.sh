#!/usr/bin/env bash
# A real single-node SLURM cluster on this machine, for the tests: Debian's slurm-wlm
# (slurmctld + slurmd) with munge authentication, configured in a private folder.
#   scripts/slurm_local.sh start DIR   # writes DIR/slurm.conf, starts munged, slurmctld, slurmd
#   scripts/slurm_local.sh stop DIR    # stops the daemons this script started
# Clients find the cluster through SLURM_CONF=DIR/slurm.conf. The daemons run as root (through
# sudo when not root); jobs run as the user who submits them. Needs slurm-wlm and munge.
set -euo pipefail
cmd=${1:?usage: slurm_local.sh start|stop DIR}
dir=${2:?usage: slurm_local.sh start|stop DIR}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
host=$(hostname -s)
if [ "$(id -u)" = 0 ]; then SUDO=(); else SUDO=(sudo -n); fi

stop_pid() { # pidfile
  [ -f "$1" ] || return 0
  local pid; pid=$(cat "$1")
  "${SUDO[@]}" kill "$pid" 2>/dev/null || true
  for _ in $(seq 50); do [ -d "/proc/$pid" ] || break; sleep 0.1; done
  "${SUDO[@]}" kill -9 "$pid" 2>/dev/null || true
  "${SUDO[@]}" rm -f "$1"
}

case "$cmd" in
start)
  # munge: the key the package made; its socket under /run/munge.
  if ! pgrep -x munged >/dev/null; then
    "${SUDO[@]}" install -d -o munge -g munge -m 0755 /run/munge
    "${SUDO[@]}" test -f /etc/munge/munge.key || { echo "slurm_local: no /etc/munge/munge.key (install munge)" >&2; exit 1; }
    "${SUDO[@]}" runuser -u munge -- /usr/sbin/munged
    touch "$dir/started_munged"
  fi
  mkdir -p "$dir/state" "$dir/spool" "$dir/log"
  cpus=$(nproc)
  mem=$(awk '/MemTotal/ {print int($2/1024*0.8)}' /proc/meminfo)
  cat > "$dir/slurm.conf" <<CONF
ClusterName=xhab-test
SlurmctldHost=$host
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CryptoType=crypto/munge
MpiDefault=none
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
SchedulerType=sched/backfill
MinJobAge=600
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$dir/slurm.conf"
  "${SUDO[@]}" /usr/sbin/slurmctld -f "$SLURM_CONF"
  "${SUDO[@]}" /usr/sbin/slurmd -f "$SLURM_CONF"
  # Up when the node is idle.
  for _ in $(seq 100); do
    state=$(sinfo -h -N -o %t 2>/dev/null | head -1 || true)
    if [ "$state" = idle ] || [ "$state" = mix ]; then echo "slurm_local: up ($SLURM_CONF)"; exit 0; fi
    sleep 0.2
  done
  echo "slurm_local: the node did not come up; logs in $dir/log" >&2
  tail -5 "$dir/log/"*.log >&2 || true
  exit 1
  ;;
stop)
  stop_pid "$dir/slurmd.pid"
  stop_pid "$dir/slurmctld.pid"
  if [ -f "$dir/started_munged" ]; then
    "${SUDO[@]}" pkill -x munged || true
    rm -f "$dir/started_munged"
  fi
  ;;
*) echo "usage: slurm_local.sh start|stop DIR" >&2; exit 2 ;;
esac

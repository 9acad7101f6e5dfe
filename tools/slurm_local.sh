#!/bin/bash
# A one-node Slurm cluster on this machine, from Debian's packages, to run a batch through
# Slurm as on a real cluster (docs/batch.md):
#
#   tools/slurm_local.sh start     install slurm-wlm and munge if missing, write a minimal
#                                  slurm.conf (this machine as the one node of partition
#                                  "local"), start munged, slurmctld and slurmd, wait until
#                                  sinfo shows the node idle
#   tools/slurm_local.sh status    what runs, and sinfo
#   tools/slurm_local.sh stop      stop the three daemons this script started
#
# It changes only Slurm's and munge's own places: /etc/slurm/slurm.conf (written only when
# absent or written by this script before), /etc/munge/munge.key (made only when absent),
# /var/lib/slurm, /var/log/slurm and /run/munge. It needs root (apt-get, the daemons).
# No accounting database is set up: `sacct` has no records here, the completed jobs are in
# /var/log/slurm/jobcomp.log (one line per job: JobId, JobName, JobState, ...).
set -euo pipefail

CONF=/etc/slurm/slurm.conf
MARK="# Written by OCG-SLAM's tools/slurm_local.sh"
STATE=/var/lib/slurm
LOGS=/var/log/slurm
PARTITION=local

say() { echo "slurm_local: $*" >&2; }
fail() { say "error: $*"; exit 1; }

need_root() {
  [ "$(id -u)" = 0 ] && return
  fail "needs root: it installs slurm-wlm and munge with apt-get (when missing), writes $CONF
and /etc/munge/munge.key, and starts munged, slurmctld and slurmd. Run it with sudo."
}

install_missing() {
  command -v slurmctld > /dev/null && command -v slurmd > /dev/null &&
    command -v munged > /dev/null && command -v sinfo > /dev/null && return
  say "installing slurm-wlm and munge (apt-get)"
  # A fresh machine often holds the package manager's lock for minutes: wait for it.
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout=600 install -y -q \
    slurm-wlm munge > /dev/null
}

write_config() {
  if [ -f "$CONF" ] && ! grep -qF "$MARK" "$CONF"; then
    say "keeping the existing $CONF (not written by this script)"
    return
  fi
  local host cpus memory
  host=$(hostname -s)
  cpus=$(nproc)
  # Leave 512 MB to the system.
  memory=$(($(awk '/MemTotal/ {print int($2 / 1024)}' /proc/meminfo) - 512))
  mkdir -p /etc/slurm
  cat > "$CONF.tmp" << EOF
$MARK: a one-node cluster for tests.
ClusterName=ocg-local
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$STATE/slurmctld
SlurmdSpoolDir=$STATE/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=$LOGS/slurmctld.log
SlurmdLogFile=$LOGS/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
ReturnToService=2
MinJobAge=3600
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$LOGS/jobcomp.log
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
  mv "$CONF.tmp" "$CONF"
  say "wrote $CONF: node $host, $cpus CPUs, $memory MB, partition $PARTITION"
}

start_munge() {
  if running munged; then return; fi
  if [ ! -f /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
  fi
  chown munge:munge /etc/munge/munge.key 2> /dev/null || true
  chmod 400 /etc/munge/munge.key
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge 2> /dev/null || true
  if id munge > /dev/null 2>&1; then
    runuser -u munge -- munged
  else
    munged --force
  fi
}

wait_idle() {
  for _ in $(seq 60); do
    if sinfo -h -N -o "%T" 2> /dev/null | grep -qx "idle"; then
      sinfo
      return
    fi
    sleep 1
  done
  sinfo || true
  fail "the node did not become idle within 60 s: see $LOGS/slurmctld.log and slurmd.log"
}

start() {
  need_root
  install_missing
  write_config
  mkdir -p "$STATE/slurmctld" "$STATE/slurmd" "$LOGS"
  start_munge
  running slurmctld || slurmctld
  running slurmd || slurmd
  # A node left "down" by an earlier stop comes back.
  scontrol update nodename="$(hostname -s)" state=resume > /dev/null 2>&1 || true
  wait_idle
}

# The daemons' pid files, as slurm.conf and munged name them.
pid_file() {
  case "$1" in
    slurmd) echo /run/slurmd.pid ;;
    slurmctld) echo /run/slurmctld.pid ;;
    munged) echo /run/munge/munged.pid ;;
  esac
}

stop() {
  need_root
  for daemon in slurmd slurmctld munged; do
    local file pid
    file=$(pid_file "$daemon")
    [ -f "$file" ] || continue
    pid=$(cat "$file")
    if kill "$pid" 2> /dev/null; then
      for _ in $(seq 20); do kill -0 "$pid" 2> /dev/null || break; sleep 0.5; done
      say "stopped $daemon ($pid)"
    fi
    rm -f "$file"
  done
}

running() {
  local file
  file=$(pid_file "$1")
  [ -f "$file" ] && kill -0 "$(cat "$file")" 2> /dev/null
}

status() {
  for daemon in munged slurmctld slurmd; do
    if running "$daemon"; then say "$daemon runs"; else say "$daemon does not run"; fi
  done
  command -v sinfo > /dev/null && sinfo 2> /dev/null || true
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  -h | --help) sed -n '2,18p' "$0" | sed 's/^# \{0,1\}//' ;;
  *) fail "usage: tools/slurm_local.sh start|stop|status (--help)" ;;
esac

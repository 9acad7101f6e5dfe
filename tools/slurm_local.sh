#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, from Debian's packages (docs/batch.md).
set -euo pipefail

usage() {
  cat <<EOF
usage: tools/slurm_local.sh start|stop|status

A one-node Slurm cluster on this machine, to run a batch through Slurm as on a real
cluster (tools/ocg_batch CONFIG --profile eval/slurm/local).

  start   installs slurm-wlm and munge when missing (apt-get, waiting up to
          OCG_APT_LOCK_WAIT seconds, default 900, for the package manager's lock), writes
          /etc/slurm/slurm.conf (this machine as the one node of partition "local", with
          its cores and memory), starts munged, slurmctld and slurmd, and waits until sinfo
          shows the node idle. Daemons already running are kept.
  stop    stops slurmd, slurmctld and munged (the pid files of slurm.conf and munged).
  status  says which daemons run and shows sinfo; exit status 0 when the node is idle
          or busy, 3 otherwise.

It changes only the system's Slurm and munge places: /etc/slurm/slurm.conf (written only
when absent or written by this script), /etc/munge/munge.key (made only when absent),
/var/lib/slurm, /var/log/slurm, /run/munge. No accounting database: finished jobs are
kept by the job completion log (/var/log/slurm/jobcomp.log), which "sacct -c" lists.
It needs root (or password-less sudo) for start and stop.
EOF
}

CONF=/etc/slurm/slurm.conf
MARK="# Written by OCG-SLAM's tools/slurm_local.sh"
STATE=/var/lib/slurm
LOGS=/var/log/slurm
PARTITION=local
LOCK_WAIT="${OCG_APT_LOCK_WAIT:-900}"

say() { echo "slurm_local: $*" >&2; }
fail() {
  say "error: $*"
  exit 1
}

# Runs as root: re-executes itself with password-less sudo, else says what it needs.
as_root() {
  [ "$(id -u)" = 0 ] && return
  if command -v sudo >/dev/null && sudo -n true 2>/dev/null; then
    exec sudo -n -- "$0" "$@"
  fi
  fail "needs root (or password-less sudo): it installs slurm-wlm and munge with apt-get
when missing, writes $CONF and /etc/munge/munge.key, and starts or stops munged,
slurmctld and slurmd. Run: sudo $0 $*"
}

install_missing() {
  local missing=()
  command -v slurmctld >/dev/null && command -v slurmd >/dev/null &&
    command -v sinfo >/dev/null || missing+=(slurm-wlm)
  command -v munged >/dev/null || missing+=(munge)
  [ "${#missing[@]}" -eq 0 ] && return
  say "installing ${missing[*]} (apt-get)"
  # A fresh machine often holds the package manager's lock for minutes: wait for it.
  DEBIAN_FRONTEND=noninteractive apt-get -o DPkg::Lock::Timeout="${LOCK_WAIT}" install -y -q \
    "${missing[@]}" >"/tmp/slurm_local_apt.$$.log" 2>&1 ||
    fail "apt-get install ${missing[*]} failed: see /tmp/slurm_local_apt.$$.log"
  rm -f "/tmp/slurm_local_apt.$$.log"
}

node_name() { hostname -s; }

# The configuration for this machine, on stdout.
config_text() {
  local host cpus memory
  host=$(node_name)
  cpus=$(nproc)
  # slurmd refuses a node announcing more memory than it has: leave 512 MB to the system.
  memory=$(($(awk '/MemTotal/ {print int($2 / 1024)}' /proc/meminfo) - 512))
  cat <<EOF
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
# No cgroups: works in containers and on machines without cgroup v2 delegation.
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU_Memory
ReturnToService=2
# Finished jobs stay visible to scontrol for an hour (Snakemake asks it when sacct cannot).
MinJobAge=3600
# No slurmdbd: the job completion log keeps the finished jobs; "sacct -c" lists them.
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/filetxt
JobCompLoc=$LOGS/jobcomp.log
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=$PARTITION Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
}

# Writes the configuration when absent or ours and different; prints "changed" then.
write_config() {
  if [ -f "$CONF" ] && ! grep -qF "$MARK" "$CONF"; then
    say "keeping $CONF: not written by this script (remove it to get the one-node cluster)"
    return
  fi
  mkdir -p "$(dirname "$CONF")"
  config_text >"$CONF.tmp"
  if [ -f "$CONF" ] && cmp -s "$CONF.tmp" "$CONF"; then
    rm -f "$CONF.tmp"
    return
  fi
  mv "$CONF.tmp" "$CONF"
  say "wrote $CONF: node $(node_name), $(nproc) CPUs, partition $PARTITION"
  echo changed
}

pid_file() {
  case "$1" in
    slurmd) echo /run/slurmd.pid ;;
    slurmctld) echo /run/slurmctld.pid ;;
    munged) echo /run/munge/munged.pid ;;
  esac
}

running() {
  local file
  file=$(pid_file "$1")
  [ -f "$file" ] && kill -0 "$(cat "$file")" 2>/dev/null
}

start_munge() {
  running munged && return
  if [ ! -f /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
  fi
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  if id munge >/dev/null 2>&1; then
    chown munge:munge /etc/munge/munge.key /run/munge /var/log/munge /var/lib/munge
    chmod 400 /etc/munge/munge.key
    runuser -u munge -- munged
  else
    chmod 400 /etc/munge/munge.key
    munged --force
  fi
}

node_state() { sinfo -h -N -o "%T" 2>/dev/null | sed -n 1p; }

wait_idle() {
  local state=""
  for _ in $(seq 60); do
    state=$(node_state)
    case "$state" in
      idle | mixed | allocated)
        sinfo
        return
        ;;
    esac
    sleep 1
  done
  sinfo >&2 || true
  fail "the node is '${state:-unknown}' after 60 s, not idle: see $LOGS/slurmctld.log and $LOGS/slurmd.log"
}

start() {
  as_root start
  install_missing
  local changed
  changed=$(write_config)
  mkdir -p "$STATE/slurmctld" "$STATE/slurmd" "$LOGS"
  start_munge
  running slurmctld || slurmctld
  running slurmd || slurmd
  if [ -n "$changed" ]; then scontrol reconfigure >/dev/null 2>&1 || true; fi
  # A node left "down" by an earlier stop comes back.
  scontrol update nodename="$(node_name)" state=resume >/dev/null 2>&1 || true
  wait_idle
}

stop_daemon() {
  local daemon=$1 file pid
  file=$(pid_file "$daemon")
  [ -f "$file" ] || return 0
  pid=$(cat "$file")
  if kill "$pid" 2>/dev/null; then
    for _ in $(seq 40); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.25
    done
    kill -0 "$pid" 2>/dev/null && fail "$daemon ($pid) still runs 10 s after SIGTERM"
    say "stopped $daemon ($pid)"
  fi
  rm -f "$file"
}

stop() {
  as_root stop
  # The node first, so the controller does not see it vanish under a running job.
  stop_daemon slurmd
  stop_daemon slurmctld
  stop_daemon munged
}

status() {
  for daemon in munged slurmctld slurmd; do
    if running "$daemon"; then say "$daemon runs"; else say "$daemon does not run"; fi
  done
  command -v sinfo >/dev/null || {
    say "Slurm is not installed"
    return 3
  }
  sinfo 2>/dev/null || true
  case "$(node_state)" in
    idle | mixed | allocated) return 0 ;;
    *) return 3 ;;
  esac
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  status) status ;;
  -h | --help) usage ;;
  *)
    usage >&2
    exit 2
    ;;
esac

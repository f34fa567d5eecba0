#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for the tests of sphd's Slurm executor and to try it
# out: Debian's slurm-wlm and munge (scripts/setup.sh installs them), run as root, everything
# (keys, config, state, logs) in DIR.
#
#   scripts/slurm-local.sh start DIR   # prints the line to source: export SLURM_CONF=DIR/slurm.conf
#   scripts/slurm-local.sh stop DIR
#
# The node has this machine's CPUs, at least 2 (two 1-CPU jobs always run at once: the tests'
# kill -9 of the daemon needs two running; a 1-CPU machine shares its core), and 2000 MB; one
# partition "debug" (the default) and a second "short" with a 1-minute limit (to test refusals).
# Ports 16817/16818 unless SLURM_LOCAL_PORT (controller; the node daemon takes the next) says
# otherwise.
set -euo pipefail
cmd=${1:-}
dir=${2:-}
if [ -z "$cmd" ] || [ -z "$dir" ] || { [ "$cmd" != start ] && [ "$cmd" != stop ]; }; then
  echo "usage: $0 start|stop DIR" >&2
  exit 64
fi
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm-local: runs as root (slurmd starts jobs as their users)" >&2
  exit 77
fi
for p in munged mungekey slurmctld slurmd scontrol sbatch; do
  if ! command -v "$p" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$p" ]; then
    echo "slurm-local: $p not found: install slurm-wlm and munge (scripts/setup.sh does)" >&2
    exit 69
  fi
done
PATH=$PATH:/usr/sbin
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)
export SLURM_CONF=$dir/slurm.conf

if [ "$cmd" = stop ]; then
  scontrol shutdown >/dev/null 2>&1 || true
  for f in slurmctld.pid slurmd.pid munged.pid; do
    if [ -f "$dir/$f" ]; then
      pid=$(cat "$dir/$f")
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; kill "$pid" 2>/dev/null || true; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null || true
      rm -f "$dir/$f"
    fi
  done
  exit 0
fi

port=${SLURM_LOCAL_PORT:-16817}
host=$(hostname -s)
cpus=$(nproc)
[ "$cpus" -ge 2 ] || cpus=2 # config_overrides below: slurmd takes the node as configured
mkdir -p "$dir/spool" "$dir/state" "$dir/munge"
chmod 700 "$dir/munge"
[ -f "$dir/munge/munge.key" ] || mungekey -c -f -k "$dir/munge/munge.key" >/dev/null 2>&1 ||
  { dd if=/dev/urandom bs=1 count=1024 of="$dir/munge/munge.key" 2>/dev/null; }
chmod 600 "$dir/munge/munge.key"
munged --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket.2" \
  --pid-file="$dir/munged.pid" --seed-file="$dir/munge/munge.seed" \
  --log-file="$dir/munged.log" -f
cat >"$dir/slurm.conf" <<EOF
ClusterName=sphdtest
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket.2
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MpiDefault=none
ReturnToService=2
SlurmdParameters=config_overrides
EnforcePartLimits=ALL
MinJobAge=600
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=2000 State=UNKNOWN
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
PartitionName=short Nodes=$host MaxTime=1 State=UP
EOF
slurmctld -c
slurmd
for _ in $(seq 100); do
  if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
    echo "export SLURM_CONF=$SLURM_CONF"
    exit 0
  fi
  sleep 0.2
done
echo "slurm-local: the node did not come up; see $dir/slurmctld.log and $dir/slurmd.log" >&2
exit 1

#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for trying deploy/slurm/animate.sbatch and for
# the tests (tests/slurm_cli.rs): Debian's slurm-wlm and munge, every file of the cluster
# (configuration, state, logs) under DIR, daemons run as root.
#
#   deploy/slurm/local-cluster.sh start DIR   # prints `export SLURM_CONF=DIR/slurm.conf`
#   deploy/slurm/local-cluster.sh stop DIR
#
# Commands (sbatch, squeue, scancel, scontrol) reach this cluster through SLURM_CONF.
set -euo pipefail
cmd=${1:?usage: local-cluster.sh start|stop DIR}
dir=${2:?usage: local-cluster.sh start|stop DIR}
mkdir -p "$dir"
dir=$(cd "$dir" && pwd)

stop() {
  for d in slurmd slurmctld; do
    if [ -f "$dir/$d.pid" ]; then
      kill "$(cat "$dir/$d.pid")" 2>/dev/null || true
      rm -f "$dir/$d.pid"
    fi
  done
}

case "$cmd" in
  stop) stop; exit 0 ;;
  start) ;;
  *) echo "local-cluster.sh: unknown command $cmd (start or stop)" >&2; exit 2 ;;
esac

for exe in munged slurmctld slurmd sbatch; do
  command -v "$exe" >/dev/null || { echo "local-cluster.sh: $exe is missing (apt-get install slurm-wlm munge)" >&2; exit 3; }
done

# munge: one daemon per machine, shared with any other cluster here; started once.
if ! pgrep -x munged >/dev/null; then
  if [ ! -s /etc/munge/munge.key ]; then
    mkdir -p /etc/munge
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
  fi
  mkdir -p /run/munge /var/lib/munge /var/log/munge
  chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge 2>/dev/null || true
  chmod 0400 /etc/munge/munge.key
  if id munge >/dev/null 2>&1; then
    runuser -u munge -- munged
  else
    munged --force
  fi
fi

host=$(hostname -s)
# slurmd -C describes this machine's CPUs and memory as slurm.conf wants them.
node=$(slurmd -C | head -1)
# Ports from the environment, so two clusters on one machine (tests run side by side) differ.
ctld_port=${SLURMCTLD_PORT:-6817}
d_port=${SLURMD_PORT:-6818}
mkdir -p "$dir/state" "$dir/spool" "$dir/log"
cat > "$dir/slurm.conf" <<CONF
ClusterName=dynray-local
SlurmctldHost=$host
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
SchedulerType=sched/backfill
MpiDefault=none
ReturnToService=2
JobRequeue=1
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
JobAcctGatherType=jobacct_gather/none
# Tasks start at once and finished jobs are forgotten soon (the tests poll squeue).
SchedulerParameters=sched_interval=1
MinJobAge=30
$node State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP OverSubscribe=YES
CONF
export SLURM_CONF="$dir/slurm.conf"
stop
slurmctld -c -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
# Up when the node is idle (seconds).
for _ in $(seq 1 60); do
  if sinfo -h -o %t 2>/dev/null | grep -qx idle; then
    echo "export SLURM_CONF=$SLURM_CONF"
    exit 0
  fi
  sleep 0.5
done
echo "local-cluster.sh: the node did not come up; logs in $dir/log" >&2
sinfo >&2 || true
exit 1

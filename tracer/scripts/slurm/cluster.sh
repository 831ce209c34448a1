#!/usr/bin/env bash
# A one-node Slurm cluster on this machine, for tests: `cluster.sh start DIR` writes
# DIR/slurm.conf naming this host as the only node (all its CPUs, no accounting, no
# cgroups, no systemd), starts munged, slurmctld and slurmd as root with their state,
# logs and PID files under DIR, and waits until the node is idle; `cluster.sh stop DIR`
# stops the three daemons by the PIDs recorded in DIR. Commands in between need
# SLURM_CONF=DIR/slurm.conf. Needs root and the Debian packages slurm-wlm and munge.
set -euo pipefail
cmd=${1:?start or stop}; dir=$(realpath -m "${2:?state directory}")

stop() {
  for name in slurmd slurmctld munged; do
    if [ -s "$dir/$name.pid" ]; then
      pid=$(cat "$dir/$name.pid")
      kill "$pid" 2>/dev/null || true
      for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
      kill -9 "$pid" 2>/dev/null || true
      rm -f "$dir/$name.pid"
    fi
  done
}

case $cmd in
stop) stop; exit 0 ;;
start) ;;
*) echo "usage: cluster.sh start|stop DIR" >&2; exit 2 ;;
esac

for b in munged slurmctld slurmd sbatch; do
  command -v "$b" >/dev/null || { echo "cluster.sh: $b not found (apt-get install slurm-wlm munge)" >&2; exit 1; }
done
mkdir -p "$dir"/{state,spool,log,munge}
host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)
cat > "$dir/slurm.conf" <<CONF
ClusterName=tracer-test
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=60 State=UP
CONF
export SLURM_CONF=$dir/slurm.conf
# munged: its key must exist (the Debian package creates /etc/munge/munge.key).
[ -s /etc/munge/munge.key ] || { echo "cluster.sh: no /etc/munge/munge.key" >&2; exit 1; }
chown munge:munge "$dir/munge" 2>/dev/null || true
munged --force --socket="$dir/munge/munge.socket" --pid-file="$dir/munged.pid" \
  --log-file="$dir/log/munged.log" --seed-file="$dir/munge/munged.seed"
slurmctld -f "$dir/slurm.conf"
slurmd -f "$dir/slurm.conf"
for _ in $(seq 100); do
  state=$(sinfo -h -o %T 2>/dev/null || true)
  [ "$state" = idle ] && { echo "cluster.sh: node $host idle ($cpus CPUs)"; exit 0; }
  sleep 0.2
done
echo "cluster.sh: the node did not become idle (state: ${state:-none}); logs in $dir/log" >&2
tail -5 "$dir"/log/*.log >&2 || true
stop
exit 1

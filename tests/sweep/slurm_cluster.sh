#!/usr/bin/env bash
# A private single-node Slurm cluster for the tests, in a folder of its own (no systemd):
#   slurm_cluster.sh start DIR   munged (own key, socket, pid file), slurmctld -D and slurmd -D
#                                in the background with their PIDs in DIR/*.pid; returns once
#                                `scontrol ping` says UP and `sinfo` shows the node idle.
#                                Writes DIR/env (export SLURM_CONF=...). Exit 77: Slurm or munge
#                                is not installed (the caller skips), 1: it did not come up.
#   slurm_cluster.sh stop DIR    stops the three daemons by their PIDs and waits for them.
# Run as root (SlurmUser=root, SlurmdUser=root). The node's CPUs and RealMemory are this
# machine's (`slurmd -C`); the ports are free ones picked at start.
set -euo pipefail

action=${1:?usage: slurm_cluster.sh start|stop DIR}
dir=${2:?usage: slurm_cluster.sh start|stop DIR}

stop() {
  local name pid
  for name in slurmd slurmctld munged; do
    [ -f "$dir/$name.pid" ] || continue
    pid=$(cat "$dir/$name.pid")
    [ -n "$pid" ] || continue
    kill -TERM "$pid" 2>/dev/null || true
  done
  # wait (bounded) for each to be gone: a state query, polled
  for name in slurmd slurmctld munged; do
    [ -f "$dir/$name.pid" ] || continue
    pid=$(cat "$dir/$name.pid")
    for _ in $(seq 1 200); do
      kill -0 "$pid" 2>/dev/null || break
      sleep 0.05
    done
    if kill -0 "$pid" 2>/dev/null; then kill -KILL "$pid" 2>/dev/null || true; fi
    rm -f "$dir/$name.pid"
  done
}

if [ "$action" = stop ]; then
  stop
  exit 0
fi
[ "$action" = start ] || { echo "slurm_cluster.sh: unknown action $action" >&2; exit 2; }

for program in munged slurmctld slurmd sbatch squeue sinfo scontrol; do
  if ! command -v "$program" >/dev/null 2>&1 && [ ! -x "/usr/sbin/$program" ]; then
    echo "slurm_cluster.sh: SKIP: '$program' is not installed (Debian: slurmctld slurmd slurm-client munge; scripts/install-deps.sh)" >&2
    exit 77
  fi
done
if [ "$(id -u)" -ne 0 ]; then
  echo "slurm_cluster.sh: SKIP: the private cluster runs its daemons as root (SlurmUser=root)" >&2
  exit 77
fi
PATH=$PATH:/usr/sbin

mkdir -p "$dir"/{spool,state,log}
trap 'status=$?; if [ $status -ne 0 ]; then stop; fi' EXIT

# munge: a fresh key, a private socket
head -c 1024 /dev/urandom > "$dir/munge.key"
chmod 600 "$dir/munge.key"
munged --force --socket="$dir/munge.sock" --key-file="$dir/munge.key" --pid-file="$dir/munged.pid" \
  --log-file="$dir/log/munged.log" --seed-file="$dir/munge.seed"
# munged forks and returns once its socket is ready; the pid file names the daemon
[ -S "$dir/munge.sock" ] || { echo "slurm_cluster.sh: munged did not create its socket" >&2; exit 1; }

read -r ctld_port slurmd_port < <(python3 -c '
import socket
s = [socket.socket() for _ in range(2)]
for x in s: x.bind(("127.0.0.1", 0))
print(*[x.getsockname()[1] for x in s])')
node=$(slurmd -C | head -n 1)   # NodeName=HOST CPUs=... RealMemory=...
node=${node% UpTime=*}
cat > "$dir/slurm.conf" <<CONF
# written by tests/sweep/slurm_cluster.sh: a private single-node cluster
ClusterName=pwsimtest
SlurmctldHost=localhost
SlurmctldPort=$ctld_port
SlurmdPort=$slurmd_port
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge.sock
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.conf.pid
SlurmdPidFile=$dir/slurmd.conf.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerParameters=batch_sched_delay=0
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/filetxt
JobCompLoc=$dir/jobcomp.txt
AccountingStorageType=accounting_storage/none
MaxArraySize=1001
SlurmdDebug=debug2
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$dir/slurm.conf"
echo "export SLURM_CONF='$dir/slurm.conf'" > "$dir/env"

slurmctld -D -i > "$dir/log/slurmctld.out" 2>&1 < /dev/null &
echo $! > "$dir/slurmctld.pid"
slurmd -D > "$dir/log/slurmd.out" 2>&1 < /dev/null &
echo $! > "$dir/slurmd.pid"

# readiness: poll the controller and the node state (bounded: 30 s)
for _ in $(seq 1 600); do
  for name in slurmctld slurmd; do
    if ! kill -0 "$(cat "$dir/$name.pid")" 2>/dev/null; then
      echo "slurm_cluster.sh: $name exited; its log:" >&2
      tail -n 20 "$dir/log/$name.out" "$dir/log/$name.log" >&2 2>/dev/null || true
      exit 1
    fi
  done
  if scontrol ping 2>/dev/null | grep -q "is UP" && [ "$(sinfo --noheader --format=%t 2>/dev/null)" = idle ]; then
    echo "slurm_cluster.sh: cluster up in $dir ($(sinfo --noheader --format='%N %c CPUs'))"
    exit 0
  fi
  sleep 0.05
done
echo "slurm_cluster.sh: the cluster did not come up within 30 s:" >&2
sinfo >&2 || true
exit 1

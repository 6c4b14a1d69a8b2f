#!/usr/bin/env bash
# A single-node Slurm cluster on localhost for tests: munged, slurmctld and slurmd with their
# own config, sockets, spool and logs under DIR (no systemd, no cgroups: proctrack/linuxproc,
# task/none). Clients reach it through SLURM_CONF=DIR/slurm.conf.
#   slurm_cluster.sh start DIR   exit 0 when the node is idle; 77 (with the reason) when the
#                                daemons cannot start here
#   slurm_cluster.sh stop DIR    stops the daemons it started
set -uo pipefail
cmd=${1:?start|stop} dir=${2:?DIR}

skip() { echo "slurm cluster: cannot start: $*" >&2; stop_daemons; exit 77; }

stop_daemons() {
  for name in slurmd slurmctld munged; do
    local pidfile=$dir/$name.pid
    [ -f "$pidfile" ] || continue
    local pid; pid=$(cat "$pidfile" 2>/dev/null || true)
    [ -n "$pid" ] && kill "$pid" 2>/dev/null
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null
    rm -f "$pidfile"
  done
}

if [ "$cmd" = stop ]; then
  stop_daemons
  exit 0
fi

for tool in munged mungekey slurmctld slurmd sbatch sinfo; do
  command -v $tool >/dev/null || skip "$tool not installed (Debian: slurm-wlm munge)"
done
[ "$(id -u)" = 0 ] || skip "slurmd must run as root to start jobs as their user"
dir=$(mkdir -p "$dir" && cd "$dir" && pwd)
mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
chmod 700 "$dir/munge"

# A free pair of ports: the daemons of another test run may hold the usual ones.
port=$((20000 + RANDOM % 20000))
host=$(hostname -s)
cpus=${CPUS:-$(nproc)} # more than the cores: latency-bound tiny tasks (slurm_bench.sh)
memory=$(awk '/MemTotal/ {print int($2 / 1024 * 0.8)}' /proc/meminfo)
cat > "$dir/slurm.conf" <<EOF
ClusterName=crowdbake-test
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$port
SlurmdPort=$((port + 1))
AuthType=auth/munge
AuthInfo=socket=$dir/munge/socket
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmdParameters=config_overrides
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
MaxArraySize=${MAX_ARRAY_SIZE:-100000}
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=test Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
export SLURM_CONF=$dir/slurm.conf

mungekey --create --keyfile "$dir/munge/munge.key" --force >/dev/null 2>&1 ||
  skip "mungekey failed"
chmod 400 "$dir/munge/munge.key"
munged --force --socket "$dir/munge/socket" --key-file "$dir/munge/munge.key" \
  --pid-file "$dir/munged.pid" --log-file "$dir/munged.log" --seed-file "$dir/munge/seed" \
  2>"$dir/munged.err" || skip "munged: $(tail -n 1 "$dir/munged.err")"
slurmctld -i 2>"$dir/slurmctld.err" || skip "slurmctld: $(tail -n 1 "$dir/slurmctld.err")"
slurmd 2>"$dir/slurmd.err" || skip "slurmd: $(tail -n 1 "$dir/slurmd.err")"

# Wait (up to 30 s) for the node to come up idle.
for _ in $(seq 150); do
  state=$(sinfo -h -N -o %t 2>/dev/null | head -n 1)
  case "$state" in idle*) echo "slurm cluster: node $host idle ($cpus CPUs), SLURM_CONF=$dir/slurm.conf"; exit 0 ;; esac
  sleep 0.2
done
skip "node $host did not come up (state '${state:-none}'); $(tail -n 2 "$dir/slurmd.log" 2>/dev/null | tr '\n' ' ')"

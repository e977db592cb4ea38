#!/usr/bin/env bash
# Opt-in test: a one-node Slurm cluster on this machine runs the CI workflow through sbatch.
#   scripts/slurm/one-node.sh [path/to/shadowbench]      (as root, or it re-runs itself with sudo)
# Installs what is missing (slurm-wlm: slurmctld, slurmd and the clients; munge; snakemake),
# writes a minimal slurm.conf for this host into its own folder (SLURM_CONF; /etc/slurm is left
# alone), starts munged (unless one answers already), slurmctld and slurmd in the background
# without systemd or cgroups, waits for the node to be idle, and runs tests/workflow_test.sh
# with the Snakemake profile scripts/workflow/profiles/slurm: the same workflow, the same checks
# as CI. The daemons it started are stopped on exit, whatever happens. Running it again is safe.
# The shadowbench binary defaults to build/harness/shadowbench (build it first).
# SHADOWBENCH_SLURM_DIR sets the folder for the config, state and logs (default
# /tmp/shadowbench-slurm); slurmctld and slurmd listen on 6817 and 6818 (free them first).
set -euo pipefail
say() { echo "one-node.sh: $*" >&2; }
fail() { say "FAIL: $*"; exit 1; }

[ "$(id -u)" -eq 0 ] || exec sudo -E "$0" "$@"
repository=$(realpath "$(dirname "$0")/../..")
sb=$(realpath "${1:-$repository/build/harness/shadowbench}")
[ -x "$sb" ] || fail "'$sb' is not an executable shadowbench: cmake --build build --target shadowbench"

missing=()
for package in slurm-wlm munge snakemake; do
  dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed" || missing+=("$package")
done
if [ ${#missing[@]} -gt 0 ]; then
  say "installing ${missing[*]}"
  apt-get update -qq
  # Without systemd, the packages' service starts are refused (policy-rc.d); this script starts them.
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${missing[@]}" > /dev/null
fi

state=${SHADOWBENCH_SLURM_DIR:-/tmp/shadowbench-slurm}
mkdir -p "$state/spool" "$state/ctld"
export SLURM_CONF=$state/slurm.conf
# Snakemake's Slurm executor reads USER (to guess an account), which a container may not set.
export USER=${USER:-$(id -un)}
host=$(hostname -s)

started=()
stop_daemons() {
  local rc=$? pid
  for pid in "${started[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${started[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
  done
  [ $rc -eq 0 ] || say "daemon logs: $state/slurmctld.log, $state/slurmd.log"
  exit $rc
}
trap stop_daemons EXIT

# A previous run's daemons (killed before its trap ran) hold the ports: stop them by their pid files.
for daemon in slurmd slurmctld; do
  if [ -s "$state/$daemon.pid" ] && pid=$(cat "$state/$daemon.pid") && [ -r "/proc/$pid/comm" ] &&
     [ "$(cat "/proc/$pid/comm")" = "$daemon" ]; then
    say "stopping $daemon $pid of an earlier run"
    kill "$pid"
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.2; done
  fi
done

if munge -n 2>/dev/null | unmunge > /dev/null 2>&1; then
  say "munged is running already"
else
  [ -s /etc/munge/munge.key ] || fail "/etc/munge/munge.key is missing: reinstall munge (it creates the key)"
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge
  runuser -u munge -- /usr/sbin/munged --pid-file=/run/munge/munged.pid
  started+=("$(cat /run/munge/munged.pid)")
  munge -n | unmunge > /dev/null || fail "munged does not answer (see /var/log/munge/munged.log)"
fi

# This host's CPUs and memory as slurmd sees them: a node that declares more is drained.
node=$(slurmd -C | head -n 1)
cpus=$(sed -n 's/.* CPUs=\([0-9]*\).*/\1/p' <<< "$node")
memory=$(sed -n 's/.* RealMemory=\([0-9]*\).*/\1/p' <<< "$node")
if [ -z "$cpus" ] || [ -z "$memory" ]; then fail "slurmd -C said '$node', without CPUs and RealMemory"; fi
# Without cgroups (a container has no systemd to delegate them): processes tracked through
# /proc (proctrack/linuxproc), CPUs bound by affinity, and memory enforced by polling each job's
# RSS against its --mem (jobacct_gather/linux with OverMemoryKill), so that a job that
# outgrows what the workflow declared fails here as it would under a cluster's cgroups.
# No accounting database: Snakemake asks scontrol for job states, so finished jobs stay
# visible for MinJobAge seconds.
cat > "$SLURM_CONF" <<EOF
ClusterName=shadowbench
SlurmctldHost=$host(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
SlurmctldPort=6817
SlurmdPort=6818
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
JobAcctGatherType=jobacct_gather/linux
JobAcctGatherFrequency=task=2
JobAcctGatherParams=OverMemoryKill
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
SchedulerType=sched/backfill
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MinJobAge=600
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

# -i: ignore a state folder an older config left (this config is the truth).
/usr/sbin/slurmctld -i -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$state/slurmctld.pid" ] && break; sleep 0.2; done
started+=("$(cat "$state/slurmctld.pid")")
/usr/sbin/slurmd -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$state/slurmd.pid" ] && break; sleep 0.2; done
started+=("$(cat "$state/slurmd.pid")")

node_state=""
for _ in $(seq 60); do
  node_state=$(sinfo -h -N -n "$host" -o %T 2>/dev/null || true)
  [ "$node_state" = "idle" ] && break
  sleep 1
done
[ "$node_state" = "idle" ] || fail "node $host is '${node_state:-not known}' after 60 s, not idle ($state/slurmd.log: $(tail -n 3 "$state/slurmd.log" 2>/dev/null))"
say "node $host idle ($cpus CPUs, $memory MiB); running the CI workflow through sbatch"

"$repository/tests/workflow_test.sh" --profile "$repository/scripts/workflow/profiles/slurm" "$sb"
say "PASS: the workflow ran through Slurm and its merged structures answer as whole builds"

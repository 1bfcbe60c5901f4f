#!/usr/bin/env bash
# Runs the Slurm job array of docs/distributed.md on a single-node Slurm cluster started here
# (Debian's slurm-wlm and munge; slurmctld and slurmd on this machine, as root), then the merge
# job with --dependency=afterok on the array, and checks that the merged image equals one
# render of the same samples (quasar compare: relative MSE of the beauty below 1e-8, i.e.
# relative differences of about 1e-4 at most; the tests see below 2e-5).
#
#   sudo scripts/slurm/single-node.sh [QUASAR_BINARY]   (default: target/release/quasar)
#
# It installs the packages when missing (apt-get), writes its configuration under
# /tmp/quasar-slurm, stops the daemons it started on exit, and prints the result, which
# docs/distributed.md records. Needs root (slurmd runs jobs as their user; munged needs its key).
set -euo pipefail
cd "$(dirname "$0")/../.."
quasar=$(realpath "${1:-target/release/quasar}")
[ -x "$quasar" ] || { echo "no quasar binary at $quasar (cargo build --release)" >&2; exit 1; }
[ "$(id -u)" = 0 ] || { echo "SKIP: run as root: it starts munged, slurmctld and slurmd" >&2; exit 77; }

# exit code 77: Slurm could not be set up here (no packages, daemons that do not start); the
# caller (.ci/run) reports a skip. Any other failure is a failure of the documented workflow.
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
  DEBIAN_FRONTEND=noninteractive apt-get install -y -q slurm-wlm munge >/dev/null ||
    { echo "SKIP: apt-get install slurm-wlm munge failed" >&2; exit 77; }
fi

work=/tmp/quasar-slurm
rm -rf "$work"
mkdir -p "$work"/{state,spool,log,parts}
host=$(hostname -s)
cpus=$(nproc)
mem=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))

# munge: a key, the daemon
install -d -m 0700 -o munge -g munge /etc/munge /var/lib/munge /var/log/munge
install -d -m 0755 -o munge -g munge /run/munge
if [ ! -s /etc/munge/munge.key ]; then
  dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
  chown munge:munge /etc/munge/munge.key
  chmod 0400 /etc/munge/munge.key
fi
pgrep -x munged >/dev/null || runuser -u munge -- munged ||
  { echo "SKIP: munged did not start" >&2; exit 77; }

cat > "$work/slurm.conf" <<CONF
ClusterName=quasar
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF="$work/slurm.conf"
cleanup() {
  for p in slurmd slurmctld; do
    [ -f "$work/$p.pid" ] && kill "$(cat "$work/$p.pid")" 2>/dev/null || true
  done
}
trap cleanup EXIT
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 60); do
  sinfo -h -o %t 2>/dev/null | grep -q idle && break
  sleep 1
done
sinfo -h -o %t 2>/dev/null | grep -q idle ||
  { echo "SKIP: the Slurm node did not come up (logs in $work/log)" >&2; exit 77; }
sinfo

# the job array of docs/distributed.md, sized for this machine: 4 shards of 64 samples
scene=$(realpath scenes/cornell-box/cornell-box.toml)
shards=4
cat > "$work/render.sbatch" <<JOB
#!/bin/bash
#SBATCH --job-name=quasar
#SBATCH --array=0-$((shards - 1))
#SBATCH --cpus-per-task=1
#SBATCH --output=$work/log/render-%a.out
"$quasar" render "$scene" --width 64 --height 64 --spp 64 --threads "\$SLURM_CPUS_PER_TASK" \\
    --shard "\$SLURM_ARRAY_TASK_ID/$shards" -o "$work/parts/part-\$SLURM_ARRAY_TASK_ID.exr" --quiet
JOB
array=$(sbatch --parsable "$work/render.sbatch")
merge=$(sbatch --parsable --dependency=afterok:"$array" --output="$work/log/merge.out" \
  --wrap "\"$quasar\" merge $work/parts/part-*.exr -o $work/merged.exr")
echo "submitted array job $array and merge job $merge (afterok:$array)"
start=$(date +%s)
while squeue -h -j "$array,$merge" 2>/dev/null | grep -q .; do
  [ $(( $(date +%s) - start )) -lt 600 ] || { echo "timed out waiting for the jobs" >&2; exit 1; }
  sleep 2
done
sacct_state=$(scontrol show job "$merge" 2>/dev/null | grep -o 'JobState=[A-Z]*' || true)
echo "merge job: ${sacct_state:-finished}"
cat "$work/log/merge.out"
[ -s "$work/merged.exr" ] || { echo "no merged image; logs in $work/log" >&2; exit 1; }

# the same samples in one render
"$quasar" render "$scene" --width 64 --height 64 --spp 64 -o "$work/single.exr" --quiet
report=$("$quasar" compare "$work/merged.exr" "$work/single.exr")
echo "$report"
rel=$(echo "$report" | awk '$1 == "beauty" {print $3}')
echo "beauty relMSE: ${rel:-?}"
awk -v r="${rel:-1}" 'BEGIN { exit !(r < 1e-8) }' || { echo "FAIL: the merged image differs from the single render" >&2; exit 1; }
echo "OK: $shards Slurm array tasks + the afterok merge job give the single render's image"

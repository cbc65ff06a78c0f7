#!/usr/bin/env bash
# strata on a real (one-node) Slurm cluster: render the Cornell box as a job array of N parts
# plus a merge job that depends on it, for N = 1, 2, 4, and check each merged image equals a
# single render of the same samples. Not part of CI.
#
# Needs Debian (12) and root: installs Debian's slurmctld, slurmd, slurm-client and munge,
# writes a one-node configuration for this host, starts munged, slurmctld and slurmd, and
# stops the daemons it started when it ends (also on failure). Usage:
#
#   sudo scripts/slurm-demo.sh [SCENE] [SPP] [SIZE]      (default: scenes/cornell-box.toml 64 256x256)
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

scene=${1:-scenes/cornell-box.toml}
spp=${2:-64}
size=${3:-256x256}
work=${STRATA_DEMO_DIR:-/tmp/strata-slurm-demo}

[ "$(id -u)" = 0 ] || { echo "slurm-demo: run as root (it installs and starts Slurm)" >&2; exit 1; }
command -v apt-get >/dev/null || { echo "slurm-demo: needs a Debian system (apt-get)" >&2; exit 1; }

log() { echo "slurm-demo: $*" >&2; }

# ---- strata and the comparison tool ----------------------------------------------------------
log "building strata (release)"
cargo build --release --quiet --bin strata --example same_render
strata="$repo/target/release/strata"
same="$repo/target/release/examples/same_render"

# ---- Slurm and munge from Debian -------------------------------------------------------------
if ! command -v slurmctld >/dev/null || ! command -v sbatch >/dev/null || ! command -v munged >/dev/null; then
    log "installing slurmctld slurmd slurm-client munge"
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurmctld slurmd slurm-client munge >/dev/null
fi

host=$(hostname -s)
cpus=$(nproc)
mem=$(awk '/MemTotal/ {print int($2 / 1024 * 0.9)}' /proc/meminfo)
state=/var/lib/strata-slurm-demo
mkdir -p "$state/ctld" "$state/d" /etc/slurm /run/munge "$work"

started=()
cleanup() {
    for pid in "${started[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${started[@]}"; do
        wait "$pid" 2>/dev/null || true
    done
    log "stopped the daemons it started (${#started[@]})"
}
trap cleanup EXIT

# ---- munge: a key, and the daemon ------------------------------------------------------------
if [ ! -s /etc/munge/munge.key ]; then
    log "creating a munge key"
    mkdir -p /etc/munge
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key status=none
fi
chown -R munge:munge /etc/munge /run/munge /var/lib/munge /var/log/munge 2>/dev/null || true
chmod 0700 /etc/munge
chmod 0400 /etc/munge/munge.key
if ! pgrep -x munged >/dev/null; then
    runuser -u munge -- /usr/sbin/munged --foreground >"$state/munged.out" 2>&1 &
    started+=($!)
    sleep 1
fi
munge -n | unmunge >/dev/null || { log "munge does not work"; exit 1; }

# ---- A one-node cluster on this host -----------------------------------------------------------
cat >/etc/slurm/slurm.conf <<EOF
# Written by strata's scripts/slurm-demo.sh: one node, this host.
ClusterName=strata-demo
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/d
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
JobAcctGatherType=jobacct_gather/none
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
NodeName=$host CPUs=$cpus RealMemory=$mem State=UNKNOWN
PartitionName=demo Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF
log "starting slurmctld and slurmd ($host, $cpus CPUs)"
slurmctld -D -i >"$state/slurmctld.out" 2>&1 &
started+=($!)
slurmd -D >"$state/slurmd.out" 2>&1 &
started+=($!)
for _ in $(seq 60); do
    if sinfo -h -o '%T' 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then break; fi
    sleep 1
done
sinfo -h -o '%T' | grep -qE '^(idle|mixed|allocated)' || { log "the node did not come up"; sinfo; exit 1; }
sinfo

# ---- The render as N parts + a merge, for N = 1, 2, 4 ---------------------------------------------
log "single render of $scene ($size, $spp spp) for comparison, 1 thread as a task has"
RAYON_NUM_THREADS=1 "$strata" render "$scene" --device cpu --size "$size" --spp "$spp" \
    --samples "0..$spp" -o "$work/single.exr" 2>"$work/single.log"
single=$(grep -o 'in [0-9.]* s' "$work/single.log" | head -1)

wait_for() {
    while squeue -h -j "$1" 2>/dev/null | grep -q .; do sleep 0.5; done
}

summary=()
for n in 1 2 4; do
    dir="$work/n$n"
    rm -rf "$dir"
    mkdir -p "$dir"
    cat >"$dir/render.sbatch" <<EOF
#!/bin/bash
#SBATCH --job-name=strata-parts
#SBATCH --array=0-$((n - 1))
#SBATCH --cpus-per-task=1
#SBATCH --output=$dir/part-%a.log
export RAYON_NUM_THREADS=\${SLURM_CPUS_PER_TASK:-1}
exec "$strata" render "$repo/$scene" --device cpu --size $size --spp $spp \\
    --part-from-env -o "$dir/part-\$SLURM_ARRAY_TASK_ID.exr"
EOF
    start=$(date +%s.%N)
    array=$(sbatch --parsable "$dir/render.sbatch")
    merge=$(sbatch --parsable --dependency="afterok:$array" --job-name=strata-merge \
        --output="$dir/merge.log" \
        --wrap "\"$strata\" merge $dir/part-*.exr -o $dir/merged.exr -o $dir/merged.png")
    wait_for "$array"
    wait_for "$merge"
    seconds=$(echo "$(date +%s.%N) - $start" | bc)
    log "N = $n: array $array and merge $merge finished in $seconds s"
    parts=$(grep -ho 'in [0-9.]* s:' "$dir"/part-*.log | grep -o '[0-9.]*' | paste -sd' ')
    log "N = $n: the parts rendered in $parts s"
    cat "$dir/merge.log"
    if "$same" "$dir/merged.exr" "$work/single.exr"; then
        summary+=("N = $n: $(printf '%.1f' "$seconds") s from submission to merged image (parts: $parts s each); equals the single render")
    else
        summary+=("N = $n: $(printf '%.1f' "$seconds") s; DIFFERS from the single render")
        failed=1
    fi
done

echo
echo "strata on Slurm ($(sinfo -V)), one node $host with $cpus CPUs, $scene at $size, $spp spp, CPU reference, 1 CPU per task (single render on 1 thread: $single):"
printf '  %s\n' "${summary[@]}"
[ -z "${failed:-}" ]

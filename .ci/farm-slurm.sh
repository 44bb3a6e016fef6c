#!/usr/bin/env bash
# A real Slurm on loopback: starts munge, slurmctld and slurmd (one node,
# 2 CPUs, private ports and state under target/ci-farm/slurm), validates the
# generated scripts with `sbatch --test-only`, submits prepare → render array
# (3 frames × 6 tiles, throttle 2) → assemble with `natura farm slurm`'s
# submit.sh, waits, checks every frame against a single-process render, and
# prints the wall time of the Slurm job against one process rendering the
# same frames. Needs root and Debian's slurm-wlm and munge packages
# (apt-get install slurm-wlm munge; .ci/run installs them) and fails without
# them (about 35 s on the tiny scene).
set -euo pipefail
missing=""
for tool in slurmctld slurmd sbatch munged; do
  command -v "$tool" >/dev/null || missing="$missing $tool"
done
if [ -n "$missing" ]; then
  echo "FAIL: not found:$missing (apt-get install slurm-wlm munge; .ci/run installs them)" >&2
  exit 1
fi
if [ "$(id -u)" != 0 ]; then
  echo "FAIL: the Slurm cluster starts munge and slurmd, which needs root" >&2
  exit 1
fi
source "$(dirname "$0")/farm-common.sh"
root="$PWD/target/ci-farm/slurm"
out="$root/out"
state="$root/state"
cpus="${NATURA_SLURM_CPUS:-2}"

stop() {
  for pid in "$state"/slurmd.pid "$state"/slurmctld.pid "$state"/munged.pid; do
    [ -f "$pid" ] && kill "$(cat "$pid")" 2>/dev/null || true
  done
}
trap stop EXIT
stop
rm -rf "$root"
mkdir -p "$state"/ctld "$state"/spool "$state"/munge "$out"

# munge: a fresh key, a private socket.
dd if=/dev/urandom of="$state/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$state/munge/munge.key"
chmod 700 "$state/munge"
munged --force --key-file="$state/munge/munge.key" --socket="$state/munge/socket" \
  --pid-file="$state/munged.pid" --log-file="$state/munged.log" --seed-file="$state/munge/seed"
export SLURM_CONF="$state/slurm.conf"
cat >"$SLURM_CONF" <<CONF
ClusterName=natura
SlurmctldHost=localhost(127.0.0.1)
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$state/munge/socket
CredType=cred/munge
SlurmctldPort=16817
SlurmdPort=16818
StateSaveLocation=$state/ctld
SlurmdSpoolDir=$state/spool
SlurmctldPidFile=$state/slurmctld.pid
SlurmdPidFile=$state/slurmd.pid
SlurmctldLogFile=$state/slurmctld.log
SlurmdLogFile=$state/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0,sched_min_interval=0
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
MaxArraySize=10001
NodeName=localhost NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=local Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
slurmctld -c
slurmd -N localhost
for _ in $(seq 60); do
  sinfo -h -o '%T' 2>/dev/null | grep -q idle && break
  sleep 1
done
sinfo

"$natura" farm slurm "$scene" --out "$out" --tiles 6 --throttle "$cpus" --cpus 1
for s in prepare render assemble; do
  sbatch --test-only "$out/slurm/$s.sbatch"
done

t0=$(date +%s.%N)
read -r prepare render assemble < <(bash "$out/slurm/submit.sh")
echo "submitted: prepare $prepare, render array $render, assemble $assemble"
while squeue -h -j "$prepare,$render,$assemble" 2>/dev/null | grep -q .; do
  sleep 0.5
done
t1=$(date +%s.%N)
for f in 0 1 2; do
  [ -f "$(printf '%s/frame_%04d.png' "$out" "$f")" ] || {
    echo "FAIL: frame $f was not assembled; logs:" >&2; tail -n 5 "$out"/logs/*.log >&2; exit 1; }
done
slurm_s=$(echo "$t1 - $t0" | bc)

# One process, all threads, the same frames (no cache: the whole job).
t0=$(date +%s.%N)
for f in 0 1 2; do
  RAYON_NUM_THREADS="$cpus" "$natura" render "$scene" --frame "$f" --out "$root/one-process" >/dev/null
done
t1=$(date +%s.%N)
one_s=$(echo "$t1 - $t0" | bc)
same_as_single_process "$out" 0 1 2
printf 'wall time, 3 frames x 6 tiles: Slurm (%s slots) %.2f s, one process (%s threads) %.2f s, ratio %.2f\n' \
  "$cpus" "$slurm_s" "$cpus" "$one_s" "$(echo "$slurm_s / $one_s" | bc -l)"

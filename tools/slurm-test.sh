#!/bin/bash
# End-to-end test of `wheelrail table slurm` on a real one-node Slurm cluster on this machine.
#
# Installs slurmctld, slurmd, slurm-client and munge from the distribution's packages when missing (Debian;
# needs root), writes a temporary slurm.conf (one node: this host with all its cores), starts munged,
# slurmctld and slurmd in the foreground as background processes of this script, submits a small table build
# (1152 points, 6 x 6 grid) as an array job of 3 shards with `sbatch --wait`, then the merge job, and compares
# the merged table byte for byte with the same table built in one process (every .npy with cmp, table.json
# without its `build` record of date, duration and threads); then loses one shard, damages another and submits
# the array job again: the task of the intact shard keeps it, the other two rebuild theirs to the same bytes
# (`table build --resume`). A trap stops every daemon by its PID on any exit and removes the temporary
# directory; nothing is left running.
#
# Usage: tools/slurm-test.sh            (from the repository root; uses target/release/wheelrail)
#   WHEELRAIL=PATH          the wheelrail executable [default: target/release/wheelrail]
#   WHEELRAIL_SKIP_SLURM=1  skip the test (prints that it was skipped; exit 0)
# Exit status 0 only if the merged table equals the one-process table and the resubmission rebuilt exactly the
# missing and the damaged shard.
set -euo pipefail

if [ "${WHEELRAIL_SKIP_SLURM:-0}" = 1 ]; then
    echo "slurm-test: SKIPPED (WHEELRAIL_SKIP_SLURM=1): the Slurm array-job build was not tested"
    exit 0
fi

fail() {
    echo "slurm-test: FAILED: $*" >&2
    exit 1
}
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f s", b - a }'; }

t_start=$(now)
repo=$(cd "$(dirname "$0")/.." && pwd)
wheelrail=$(realpath "${WHEELRAIL:-$repo/target/release/wheelrail}" 2>/dev/null) ||
    fail "no wheelrail executable at ${WHEELRAIL:-$repo/target/release/wheelrail} (run: cargo build --release -p wheelrail-cli, or make slurm-test)"
[ -x "$wheelrail" ] || fail "$wheelrail is not executable"

# --- install Slurm and munge when missing -------------------------------------------------------------------
missing=0
for c in munged slurmctld slurmd sbatch sinfo; do
    command -v "$c" >/dev/null || PATH="$PATH:/usr/sbin:/sbin" command -v "$c" >/dev/null || missing=1
done
export PATH="$PATH:/usr/sbin:/sbin"
t_install=$(now)
if [ "$missing" = 1 ]; then
    [ "$(id -u)" = 0 ] || fail "Slurm is not installed and this is not root: install slurmctld slurmd slurm-client munge (apt-get install), run as root, or set WHEELRAIL_SKIP_SLURM=1 to skip this test"
    command -v apt-get >/dev/null || fail "Slurm is not installed and there is no apt-get: install slurmctld slurmd slurm-client munge, or set WHEELRAIL_SKIP_SLURM=1 to skip this test"
    echo "slurm-test: installing slurmctld slurmd slurm-client munge"
    pkgs=(slurmctld slurmd slurm-client munge)
    apt_log=$(mktemp /tmp/wheelrail-slurm-apt.XXXXXX)
    # the packages' own services stay stopped (policy-rc.d 101: this test starts its own daemons)
    if ! (
        if [ ! -e /usr/sbin/policy-rc.d ]; then
            trap 'rm -f /usr/sbin/policy-rc.d' EXIT
            printf '#!/bin/sh\nexit 101\n' >/usr/sbin/policy-rc.d
            chmod 755 /usr/sbin/policy-rc.d
        fi
        export DEBIAN_FRONTEND=noninteractive
        apt-get install -y -q --no-install-recommends "${pkgs[@]}" ||
            { apt-get update -q && apt-get install -y -q --no-install-recommends "${pkgs[@]}"; }
    ) >"$apt_log" 2>&1; then
        tail -n 20 "$apt_log" >&2
        rm -f "$apt_log"
        fail "apt-get could not install ${pkgs[*]}; install them by hand or set WHEELRAIL_SKIP_SLURM=1 to skip this test"
    fi
    rm -f "$apt_log"
fi
install_time=$(since "$t_install")
[ "$(id -u)" = 0 ] || fail "the test cluster runs its daemons as root (SlurmUser=root); run as root or set WHEELRAIL_SKIP_SLURM=1 to skip this test"

# --- the temporary cluster ------------------------------------------------------------------------------------
tmp=$(mktemp -d /tmp/wheelrail-slurm.XXXXXX)
pids=()
# PIDs of processes of this test's cluster still running
ours() {
    pgrep -f "$tmp"
    for p in $(pgrep -x slurmstepd); do
        grep -qsF "SLURM_CONF=$tmp/" "/proc/$p/environ" && echo "$p"
    done
}
cleanup() {
    local status=$?
    set +e
    if [ -n "${SLURM_CONF:-}" ] && [ "${#pids[@]}" -gt 1 ]; then
        scancel --quiet --user=root >/dev/null 2>&1
    fi
    # stop in reverse order of start: slurmd, slurmctld, munged
    for ((i = ${#pids[@]} - 1; i >= 0; i--)); do
        kill -TERM "${pids[i]}" 2>/dev/null
        for _ in $(seq 50); do kill -0 "${pids[i]}" 2>/dev/null || break; sleep 0.1; done
        kill -KILL "${pids[i]}" 2>/dev/null
        wait "${pids[i]}" 2>/dev/null
    done
    # job steps (slurmstepd, daemons of their own: this cluster's have its SLURM_CONF in their environment)
    # and anything else with this directory on its command line
    for _ in $(seq 100); do [ -z "$(ours)" ] && break; sleep 0.1; done
    left=$(ours)
    if [ -n "$left" ]; then
        echo "slurm-test: still running after the cluster stopped, killing: $(ps -o pid=,args= -p ${left//$'\n'/,})" >&2
        kill -KILL $left 2>/dev/null
        status=1
    fi
    if [ "$status" != 0 ]; then
        for f in "$tmp"/log/*.log; do
            [ -f "$f" ] && { echo "--- $f (last 30 lines)" >&2; tail -n 30 "$f" >&2; }
        done
    fi
    rm -rf "$tmp"
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

mkdir -p "$tmp"/{munge,state,spool,log,run}
chmod 700 "$tmp/munge"
node=$(hostname -s)
cpus=$(nproc)
key="$tmp/munge/munge.key"
dd if=/dev/urandom of="$key" bs=1024 count=1 status=none # this cluster's own key; /etc/munge is not used
chmod 400 "$key"
socket="$tmp/munge/munge.socket"
export SLURM_CONF="$tmp/slurm.conf"
cat >"$SLURM_CONF" <<EOF
# temporary one-node cluster of tools/slurm-test.sh
ClusterName=wheelrailtest
SlurmctldHost=$node(127.0.0.1)
SlurmctldPort=16817
SlurmdPort=16818
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$socket
CredType=cred/munge
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldPidFile=$tmp/run/slurmctld.pid
SlurmdPidFile=$tmp/run/slurmd.pid
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
SlurmctldDebug=info
SlurmdDebug=info
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
ReturnToService=2
JobCompType=jobcomp/none
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MailProg=/bin/true
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
EOF

t_cluster=$(now)
munged --foreground --force --key-file="$key" --socket="$socket" --pid-file="$tmp/run/munged.pid" \
    --seed-file="$tmp/munge/munge.seed" --log-file="$tmp/log/munged.log" >"$tmp/log/munged.out" 2>&1 &
pids+=($!)
for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not start (see $tmp/log/munged.log)"
slurmctld -D -f "$SLURM_CONF" >"$tmp/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" >"$tmp/log/slurmd.out" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 120); do
    state=$(sinfo -h -N -n "$node" -o %T 2>/dev/null || true)
    [ "$state" = idle ] && break
    for p in "${pids[@]}"; do kill -0 "$p" 2>/dev/null || fail "a daemon (PID $p) exited while the cluster started"; done
    sleep 0.5
done
[ "$state" = idle ] || fail "node $node not idle after 60 s (state: '${state:-none}')"
cluster_time=$(since "$t_cluster")
echo "slurm-test: one-node cluster up ($node, $cpus CPUs) in $cluster_time"

# --- the table build as an array job, the merge job, and the same table in one process ------------------------
job="$tmp/job dir" # a space: the scripts must quote their paths
params="$tmp/params 6x6.toml"
axes="$repo/tests/fixtures/small-axes.toml"
printf '[grid]\nnx = 6\nny = 6\n' >"$params"
"$wheelrail" table slurm --shards 3 --out "$job" --params "$params" --axes "$axes" --cpus-per-task 1 \
    --time 00:10:00 --verify-samples 0 >/dev/null 2>&1
t_job=$(now)
sbatch --wait --quiet "$job/build.sbatch" || fail "the array job failed (logs: $job/logs)"
sbatch --wait --quiet "$job/merge.sbatch" || fail "the merge job failed (logs: $job/logs)"
job_time=$(since "$t_job")
for k in 1 2 3; do
    compgen -G "$job/logs/build-*_$k.out" >/dev/null || fail "no log of array task $k: it did not run under Slurm"
done
RAYON_NUM_THREADS=$cpus "$wheelrail" table build --params "$params" --axes "$axes" --out "$tmp/single" 2>/dev/null

merged="$job/table"
[ -f "$merged/table.json" ] || fail "no merged table at $merged"
(cd "$tmp/single" && ls) >"$tmp/single.files"
(cd "$merged" && ls) >"$tmp/merged.files"
cmp -s "$tmp/single.files" "$tmp/merged.files" || fail "the merged table has other files: $(cat "$tmp/merged.files" | tr '\n' ' ')"
arrays=0
for f in "$tmp/single"/*.npy; do
    cmp "$f" "$merged/$(basename "$f")" || fail "$(basename "$f") differs between the Slurm build and the one-process build"
    arrays=$((arrays + 1))
done
[ "$arrays" -ge 6 ] || fail "only $arrays .npy arrays compared"
python3 - "$tmp/single/table.json" "$merged/table.json" <<'EOF' || fail "table.json differs beyond its build record"
import json, sys
a, b = (json.load(open(p)) for p in sys.argv[1:])
assert b["build"]["merged_shards"] == 3, b["build"]
for s in (a, b):
    del s["build"]
sys.exit(0 if a == b else 1)
EOF
# verification reads the merged table like the one-process one (same sample points, same report)
v1=$("$wheelrail" table verify "$tmp/single" --samples 50 --json 2>/dev/null || true)
v2=$("$wheelrail" table verify "$merged" --samples 50 --json 2>/dev/null || true)
[ -n "$v1" ] && [ "$v1" = "$v2" ] || fail "table verify reports differ: $v1 / $v2"

# a resubmitted array job recomputes only what is missing or damaged (build --resume): shard 2 lost, one
# array of shard 3 damaged, shard 1 intact; the rebuilt shards are the first ones byte for byte
cp -r "$job/shards" "$tmp/shards-first"
rm -r "$job/shards/2"
printf 'x' >>"$job/shards/3/converged.npy"
t_resume=$(now)
resubmitted=$(sbatch --wait --parsable "$job/build.sbatch") || fail "the resubmitted array job failed (logs: $job/logs)"
resubmitted=${resubmitted%%;*}
resume_time=$(since "$t_resume")
grep -q "already holds this build" "$job/logs/build-${resubmitted}_1.out" ||
    fail "the resubmitted task 1 did not keep its built shard: $(cat "$job/logs/build-${resubmitted}_1.out")"
for k in 2 3; do
    grep -q "^wrote " "$job/logs/build-${resubmitted}_$k.out" ||
        fail "the resubmitted task $k did not rebuild its shard: $(cat "$job/logs/build-${resubmitted}_$k.out")"
done
for k in 1 2 3; do
    for f in "$tmp/shards-first/$k"/*.npy; do
        cmp "$f" "$job/shards/$k/$(basename "$f")" || fail "shard $k's $(basename "$f") differs after the resubmission"
    done
done

echo "slurm-test: PASSED: 3-shard array job on Slurm merged to the same table as one process ($arrays arrays + table.json)"
echo "slurm-test: PASSED: the resubmitted array job kept shard 1 and rebuilt the lost shard 2 and the damaged shard 3"
echo "slurm-test: times: install $install_time, cluster start $cluster_time, jobs (array + merge) $job_time, resubmission $resume_time, total $(since "$t_start")"

#!/usr/bin/env bash
# A real cluster (issue 33 §3): a single-node Slurm from Debian's packages (munge, slurmctld, slurmd,
# slurm-client) started on localhost in a scratch folder, examples/perceptual-test/slurm.sh submitted as
# a real job array with the merge job depending on it; the merged stimuli and key must be byte-identical
# to a local unsharded run. Then a lost shard is re-run alone (the README's resume recipe) and merged again.
# Skips (77) only where the packages are not installed or slurmd cannot run (it needs root).
set -euo pipefail
TH=$1; EX=$2; TW=${3:-}   # TW: a build of another -march (cli.width_build), run by shard 1 (issue 44)
for c in munged slurmctld slurmd sbatch scontrol sinfo; do
	command -v "$c" >/dev/null || [[ -x /usr/sbin/$c ]] || { echo "skipped: $c is missing (scripts/setup-deps installs munge slurmctld slurmd slurm-client)"; exit 77; }
done
((EUID == 0)) || { echo "skipped: slurmd runs jobs as their users and must start as root"; exit 77; }
PATH=/usr/sbin:$PATH
T=$(mktemp -d)
pids=()
cleanup() {
	for p in "${pids[@]}"; do kill "$p" 2>/dev/null || true; done
	for p in "${pids[@]}"; do wait "$p" 2>/dev/null || true; done
	rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "slurm test: $*"; for f in "$T"/log/* "$T"/work/*.log; do [[ -f "$f" ]] && { echo "== $f"; tail -20 "$f"; }; done; exit 1; }

# munge: its own key, socket and files under $T.
mkdir -p "$T/munge" "$T/log" "$T/state" "$T/spool" "$T/work"
chmod 700 "$T/munge"
dd if=/dev/urandom of="$T/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$T/munge/munge.key"
munged --force --foreground --socket="$T/munge/socket" --key-file="$T/munge/munge.key" --pid-file="$T/munge/pid" \
	--seed-file="$T/munge/seed" --log-file="$T/log/munged.log" >>"$T/log/munged.out" 2>&1 &
pids+=($!)

# Free ports for slurmctld and slurmd (two listening sockets the kernel picked, closed again).
read -r p1 p2 < <(/usr/bin/python3 -c 'import socket
a, b = socket.socket(), socket.socket()
a.bind(("127.0.0.1", 0)); b.bind(("127.0.0.1", 0))
print(a.getsockname()[1], b.getsockname()[1])')
node=$(hostname -s)
mem=$(awk '/MemTotal/ { print int($2 / 1024 * 0.8) }' /proc/meminfo)
cat >"$T/slurm.conf" <<CONF
ClusterName=talkhead-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=root
SlurmctldPort=$p1
SlurmdPort=$p2
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$T/munge/socket
StateSaveLocation=$T/state
SlurmdSpoolDir=$T/spool
SlurmctldPidFile=$T/slurmctld.pid
SlurmdPidFile=$T/slurmd.pid
SlurmctldLogFile=$T/log/slurmctld.log
SlurmdLogFile=$T/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
SwitchType=switch/none
ReturnToService=2
MinJobAge=600
NodeName=$node NodeAddr=127.0.0.1 CPUs=$(nproc) RealMemory=$mem State=UNKNOWN
PartitionName=test Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$T/slurm.conf
slurmctld -D -f "$SLURM_CONF" >>"$T/log/slurmctld.out" 2>&1 &
pids+=($!)
slurmd -D -f "$SLURM_CONF" -N "$node" >>"$T/log/slurmd.out" 2>&1 &
pids+=($!)
for _ in $(seq 1 60); do
	[[ "$(sinfo -h -o %T 2>/dev/null)" == idle* ]] && break
	sleep 1
done
[[ "$(sinfo -h -o %T 2>/dev/null)" == idle* ]] || fail "the node never became idle: $(sinfo 2>&1 | tr '\n' ' ')"
echo "slurm: node $node idle (slurmctld :$p1, slurmd :$p2)"

# 4 small stimuli of the thesis's manifest, 3 shards.
head -n 7 "$EX/emotions.csv" | sed 's/640x360/160x90/' >"$T/m.csv"
# Jobs find talkhead on the PATH (as on a cluster with the package installed).
bin=$(cd "$(dirname "$TH")" && pwd)
[[ "$(basename "$TH")" == talkhead ]] || { mkdir -p "$T/bin"; ln -s "$(cd "$(dirname "$TH")" && pwd)/$(basename "$TH")" "$T/bin/talkhead"; bin=$T/bin; }
if [[ -n "$TW" ]]; then
	# A cluster of mixed CPUs: shard 1 runs on a "node" whose talkhead is the other width's build.
	[[ -x "$TW" ]] || fail "no second-width build at $TW"
	mkdir -p "$T/mixed"
	printf '#!/bin/sh\nif [ "${SLURM_ARRAY_TASK_ID:-}" = 1 ]; then exec "%s" "$@"; fi\nexec "%s" "$@"\n' \
		"$(cd "$(dirname "$TW")" && pwd)/$(basename "$TW")" "$bin/talkhead" >"$T/mixed/talkhead"
	chmod +x "$T/mixed/talkhead"
	bin=$T/mixed
	echo "slurm: shard 1 runs $("$TW" --version), the others $("$TH" --version)"
fi
submit() { sbatch --parsable --chdir="$T/work" --export="ALL,PATH=$bin:$PATH" --mem=1G "$@"; }
wait_job() {  # until the job (all its array tasks) has ended; its final states
	local id=$1 states
	for _ in $(seq 1 300); do
		states=$(scontrol show job "$id" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | sort -u | tr '\n' ' ')
		[[ -n "$states" && ! "$states" =~ PENDING|RUNNING|CONFIGURING|COMPLETING ]] && { echo "$states"; return; }
		grep -q 'Reason=DependencyNeverSatisfied' <<<"$(scontrol show job "$id" 2>/dev/null)" && { echo "DEPENDENCY_NEVER_SATISFIED"; return; }
		sleep 1
	done
	echo "TIMEOUT $states"
}
array=$(submit --array=0-2 "$EX/slurm.sh" "$T/m.csv" "$T/out" 9 3)
merge=$(submit --dependency=afterok:"$array" --wrap "talkhead batch --merge $T/out/merged $T/out/shards/* -q")
echo "slurm: array job $array, merge job $merge (after it)"
s=$(wait_job "$merge")
[[ "$s" == "JobState=COMPLETED " ]] || fail "merge job ended $s; array: $(wait_job "$array")"
[[ "$(wait_job "$array")" == "JobState=COMPLETED " ]] || fail "the array did not complete"
test "$(ls "$T/out/shards")" = "$(printf '0\n1\n2')" || fail "shards: $(ls "$T/out/shards" | tr '\n' ' ')"

# The same stimuli and key as a local unsharded run.
"$TH" batch "$T/m.csv" -o "$T/local" --seed 9 -q
cmp "$T/local/key.csv" "$T/out/merged/key.csv"
n=0
for f in "$T/local"/*.mp4; do cmp "$f" "$T/out/merged/$(basename "$f")"; n=$((n + 1)); done
test "$n" = 4
echo "slurm: merged key and $n stimuli equal the local run's"

# Resume: a shard lost (its node failed) is re-run alone, then merged again, into the same result.
rm -rf "$T/out/shards/1" "$T/out/merged"
again=$(submit --array=1 "$EX/slurm.sh" "$T/m.csv" "$T/out" 9 3)
[[ "$(wait_job "$again")" == "JobState=COMPLETED " ]] || fail "the re-run shard did not complete"
# A merge with a shard missing says which stimuli are in none (exit 1, key.csv marks them 'missing');
# with all of them it is the same as before.
if "$TH" batch --merge "$T/out/partial" "$T/out/shards/0" "$T/out/shards/2" -q 2>"$T/partial.err"; then fail "a merge without shard 1 succeeded"; fi
cat "$T/partial.err"
grep -q "1 stimuli are in no shard yet" "$T/partial.err"
test "$(grep -c ',missing,' "$T/out/partial/key.csv")" = 1
"$TH" batch --merge "$T/out/merged" "$T/out/shards/"* -q
cmp "$T/local/key.csv" "$T/out/merged/key.csv"
for f in "$T/local"/*.mp4; do cmp "$f" "$T/out/merged/$(basename "$f")"; done
echo "slurm: ok"

#!/usr/bin/env bash
# examples/perceptual-test (issue 14): the GNU parallel recipe run locally (2 shards, merged) gives the
# unsharded run's key; the Slurm script and the recipe parse (bash -n); the Kubernetes Job is an Indexed
# Job whose shard count matches its completions; the thesis's emotion manifest is valid (one shard renders).
set -euo pipefail
TH=$1; EX=$2
command -v parallel >/dev/null || { echo "skipped: GNU parallel not installed (scripts/setup-deps installs it)"; exit 77; }
T=$(mktemp -d); trap 'rm -rf "$T"' EXIT
head -n 7 "$EX/emotions.csv" | sed 's/640x360/160x90/' >"$T/m.csv"  # 2 comments, the header, 4 stimuli
TALKHEAD="$TH" bash "$EX/run-parallel.sh" "$T/m.csv" "$T/p" 2 9
"$TH" batch "$T/m.csv" -o "$T/u" --seed 9 -q
cmp "$T/u/key.csv" "$T/p/key.csv"
for f in "$T/u"/*.mp4; do cmp "$f" "$T/p/$(basename "$f")"; done
bash -n "$EX/slurm.sh"
bash -n "$EX/run-parallel.sh"
/usr/bin/python3 - "$EX/k8s-job.yaml" <<'PY'
import re, sys, yaml
job = yaml.safe_load(open(sys.argv[1]))
assert job["kind"] == "Job" and job["apiVersion"] == "batch/v1", job["kind"]
spec = job["spec"]
assert spec["completionMode"] == "Indexed", spec
args = " ".join(spec["template"]["spec"]["containers"][0]["args"])
shards = int(re.search(r"--shard \$JOB_COMPLETION_INDEX/(\d+)", args).group(1))
assert shards == spec["completions"], (shards, spec["completions"])
PY
grep -q '^FROM debian:12' "$EX/Containerfile"
grep -q 'scripts/setup-deps' "$EX/Containerfile"
# The full manifest is valid and renders (one of its 23 stimuli).
"$TH" batch "$EX/emotions.csv" -o "$T/e" --shard 0/23 -q
test "$(grep -c ',ok,' "$T/e/key.csv")" = 1
test "$(tail -n +2 "$T/e/key.csv" | wc -l)" = 23
echo "perceptual-test example: ok"

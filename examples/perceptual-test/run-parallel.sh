#!/usr/bin/env bash
# GNU parallel recipe: render a manifest in N shards, each in a folder of its own, then merge them.
#   local:     examples/perceptual-test/run-parallel.sh MANIFEST OUTDIR [N] [SEED]
#   over ssh:  PARALLEL_HOSTS=host1,host2 examples/perceptual-test/run-parallel.sh …   (talkhead installed on
#              every host and OUTDIR on a file system they share; otherwise add --return/--cleanup)
set -euo pipefail
manifest="$1"; out="$2"; n="${3:-$(nproc)}"; seed="${4:-1}"
th="${TALKHEAD:-talkhead}"
hosts=()
[ -n "${PARALLEL_HOSTS:-}" ] && hosts=(-S "$PARALLEL_HOSTS")
mkdir -p "$out/shards"
# One shard per job; --threads 1 so N jobs use N cores. A failing shard does not stop the others.
parallel --will-cite --halt never "${hosts[@]}" --jobs "$n" \
	"$th" batch "$manifest" -o "$out/shards/{}" --seed "$seed" --shard "{}/$n" --threads 1 -q ::: $(seq 0 $((n - 1))) || true
"$th" batch --merge "$out" "$out"/shards/* -q

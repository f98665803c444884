#!/usr/bin/env bash
# Slurm job array: one shard per array task, then a merge job that waits for all of them.
#   jid=$(sbatch --parsable --array=0-15 examples/perceptual-test/slurm.sh MANIFEST OUTDIR SEED 16)
#   sbatch --dependency=afterok:$jid --wrap "talkhead batch --merge OUTDIR/merged OUTDIR/shards/*"
# SHARDS (the 4th argument) is the shard count of the whole run: give it always, so that re-running only
# the shards that failed (sbatch --array=3,7 … SEED 16) renders the same rows as the first run did.
#SBATCH --job-name=talkhead-stimuli
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=01:00:00
#SBATCH --output=talkhead-%A_%a.log
set -euo pipefail
manifest="$1"; out="$2"; seed="${3:-1}"; shards="${4:?give the shard count of the whole run: the size of the first array, e.g. 16 for --array=0-15}"
shard="${SLURM_ARRAY_TASK_ID:?run as a job array (sbatch --array=0-N)}"
mkdir -p "$out/shards"
exec talkhead batch "$manifest" -o "$out/shards/$shard" --seed "$seed" --shard "$shard/$shards" --threads "${SLURM_CPUS_PER_TASK:-2}" -q

#!/usr/bin/env bash
# Slurm job array: one shard per array task, then a merge job that waits for all of them.
#   sbatch --array=0-15 examples/perceptual-test/slurm.sh MANIFEST OUTDIR SEED
#   sbatch --dependency=afterany:<array job id> --wrap "talkhead batch --merge OUTDIR OUTDIR/shards/*"
#SBATCH --job-name=talkhead-stimuli
#SBATCH --cpus-per-task=2
#SBATCH --mem=4G
#SBATCH --time=01:00:00
#SBATCH --output=talkhead-%A_%a.log
set -euo pipefail
manifest="$1"; out="$2"; seed="${3:-1}"
shard="${SLURM_ARRAY_TASK_ID:?run as a job array (sbatch --array=0-N)}"
count="${SLURM_ARRAY_TASK_COUNT:?run as a job array}"
mkdir -p "$out/shards"
exec talkhead batch "$manifest" -o "$out/shards/$shard" --seed "$seed" --shard "$shard/$count" --threads "${SLURM_CPUS_PER_TASK:-2}" -q

#!/usr/bin/env bash
# Submits a beamflow sweep to Slurm as a job array of N shards plus a merge job that runs
# once every shard has succeeded:
#
#   scripts/slurm/submit-sweep.sh SWEEP.toml OUTDIR N [SBATCH OPTION...]
#
#   array:  sbatch --array=1-N [OPTIONS] sweep-array.sbatch SWEEP.toml OUTDIR N
#           → OUTDIR/shard-k.h5, logs in OUTDIR/logs/
#   merge:  sbatch --dependency=afterok:ARRAY --kill-on-invalid-dep=yes
#                  sweep-merge.sbatch OUTDIR N  → OUTDIR.h5 (+ .net_power.png, .best.md)
#
# The options go to the array only and come after the script's own, so they override them:
# `--cpus-per-task=8 --time=01:00:00`, or `--array=3` to resubmit shard 3 alone. Partition and
# account for both jobs come from sbatch's SBATCH_PARTITION / SBATCH_ACCOUNT. Rerunning the
# same command resumes: complete shards do nothing, interrupted ones continue from their
# `.parts/`. beamflow is resolved here (BEAMFLOW, else PATH) and that build runs every job.
# Prints "ARRAY_JOB_ID MERGE_JOB_ID" on stdout, the rest on stderr.
set -euo pipefail

die() {
    echo "submit-sweep.sh: $*" >&2
    exit 2
}

[ $# -ge 3 ] || die "usage: submit-sweep.sh SWEEP.toml OUTDIR N [SBATCH OPTION...]"
sweep=$1
outdir=${2%/}
shards=$3
shift 3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

[[ $shards =~ ^[1-9][0-9]*$ ]] || die "shard count N must be a positive integer, got '$shards'"
[ -f "$sweep" ] || die "sweep file '$sweep' not found"
command -v sbatch >/dev/null || die "sbatch not found: is this a Slurm login node?"
beamflow=$(command -v "${BEAMFLOW:-beamflow}") ||
    die "'${BEAMFLOW:-beamflow}' not found: put beamflow on PATH or set BEAMFLOW"
export BEAMFLOW=$beamflow

mkdir -p "$outdir/logs"
name=$(basename "$sweep" .toml)
name=${name%.sweep}
array=$(sbatch --parsable --job-name="$name" --array="1-$shards" \
    --output="$outdir/logs/%x-%A_%a.out" "$@" \
    "$here/sweep-array.sbatch" "$sweep" "$outdir" "$shards")
array=${array%%;*}
merge=$(sbatch --parsable --job-name="$name-merge" \
    --dependency="afterok:$array" --kill-on-invalid-dep=yes \
    --output="$outdir/logs/%x-%j.out" \
    "$here/sweep-merge.sbatch" "$outdir" "$shards")
merge=${merge%%;*}
echo "submitted $sweep: shards = job $array, merge = job $merge → $outdir.h5 (logs in $outdir/logs)" >&2
echo "$array $merge"

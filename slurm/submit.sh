#!/bin/bash
# Submit a slipstick campaign to Slurm (run it from anywhere; paths are made absolute).
#
#   slurm/submit.sh [--slices N] CAMPAIGN.toml OUT [sbatch options ...] [-- study run options]
#
# Without --slices: one job (slurm/campaign.sbatch); resubmit the same command to resume.
# With --slices N: a job array of N tasks, each computing a deterministic slice of the cases
# into OUT/slices/<k>, then a dependent job (afterany) that merges them into OUT and assembles
# OUT/<name>.nc.  Resubmitting the same command resumes every slice and merges again.
# sbatch options (e.g. --ntasks=32 --time=04:00:00 --partition=compute) apply to the campaign
# job or to every array task; add %M to throttle, e.g. `--slices 16 --array-limit 4`.
# Prints the job ids (campaign job, or array job then merge job).

set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
slices=""
limit=""
while [[ $# -gt 0 ]]; do
    case $1 in
        --slices) slices=$2; shift 2 ;;
        --array-limit) limit=$2; shift 2 ;;
        -h | --help) sed -n '2,14p' "${BASH_SOURCE[0]}"; exit 0 ;;
        *) break ;;
    esac
done
if [[ $# -lt 2 ]]; then
    echo "usage: submit.sh [--slices N [--array-limit M]] CAMPAIGN OUT [sbatch opts] [-- run opts]" >&2
    exit 2
fi
campaign=$(realpath "$1")
out=$(realpath -m "$2")
shift 2
sbatch_opts=()
while [[ $# -gt 0 && $1 != -- ]]; do
    sbatch_opts+=("$1")
    shift
done
[[ $# -gt 0 ]] && shift  # the --
run_opts=("$@")

mkdir -p "$out/logs"
export_vars="ALL,SLIPSTICK_SLURM_DIR=$here"

if [[ -z $slices ]]; then
    sbatch --parsable --output="$out/logs/slurm-%x-%j.out" --export="$export_vars" \
        "${sbatch_opts[@]}" "$here/campaign.sbatch" "$campaign" "$out" "${run_opts[@]}"
    exit 0
fi
if ! [[ $slices =~ ^[1-9][0-9]*$ ]]; then
    echo "--slices must be a positive integer" >&2
    exit 2
fi
array_job=$(sbatch --parsable --output="$out/logs/slurm-%x-%A_%a.out" \
    --export="$export_vars,SLIPSTICK_SLICES=$slices" --array="0-$((slices - 1))${limit:+%$limit}" \
    "${sbatch_opts[@]}" "$here/campaign.sbatch" "$campaign" "$out" "${run_opts[@]}")
array_job=${array_job%%;*}
merge_job=$(sbatch --parsable --output="$out/logs/slurm-%x-%j.out" --export="$export_vars" \
    --dependency="afterany:$array_job" "$here/merge.sbatch" "$campaign" "$out")
echo "$array_job"
echo "${merge_job%%;*}"

#!/usr/bin/env bash
# Proves the Slurm recipe of docs/sweeps.md on a real Slurm: starts a one-node cluster on
# localhost, submits a shipped sweep with scripts/slurm/submit-sweep.sh as a job array of 4
# shards plus the dependent merge job, and checks that the merged table is the single-process
# run's, byte for byte. Then deletes one shard and resubmits that array task alone, then the
# whole array (which must recompute nothing): the documented ways to resume, each checked the
# same way.
#
# Compared with `cmp`, whole files: the merged HDF5 table against `beamflow sweep` run in one
# process (the file carries no timestamp: every attribute, the sweep and base-case texts and
# every /table dataset must be the same bytes), and the best-case table (.best.md) and the
# figure (.net_power.png, .svg) the merge writes against the single run's.
#
# Installs Debian's slurm-wlm and munge with apt-get when Slurm or munge is missing, and fails
# with the reason when it cannot: the test never passes without running. Needs root (slurmd
# starts jobs as their user); without it, re-runs itself through passwordless sudo. Every
# daemon it starts is stopped, and its temporary directory removed, on any exit.
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)

sweep=cases/placement-frame.sweep.toml
shards=4
per_shard=960 # the sweep's 64 × 60 cases, dealt round-robin to 4 shards
job_timeout=180

fail() {
    echo "slurm test FAILED: $*" >&2
    exit 1
}

# Build as the calling user, before any sudo. BEAMFLOW (or the first argument) names a
# binary to use instead.
BEAMFLOW=${1:-${BEAMFLOW:-}}
if [ -z "$BEAMFLOW" ]; then
    cargo build --release --quiet
    BEAMFLOW="$repo/${CARGO_TARGET_DIR:-target}/release/beamflow"
fi
[ -x "$BEAMFLOW" ] || fail "beamflow binary '$BEAMFLOW' not found"
export BEAMFLOW

if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1 && sudo -n true 2>/dev/null; then
        exec sudo -n bash "$0" "$BEAMFLOW"
    fi
    fail "needs root to start slurmd (it runs each job as its user), and passwordless sudo is not available"
fi

missing_tools() {
    local t missing=()
    for t in sbatch squeue scontrol sinfo scancel slurmctld slurmd munged mungekey munge unmunge; do
        command -v "$t" >/dev/null 2>&1 || missing+=("$t")
    done
    echo "${missing[*]}"
}
if [ -n "$(missing_tools)" ]; then
    # shellcheck source=SCRIPTDIR/lib/apt-install.sh
    source scripts/lib/apt-install.sh
    start=$SECONDS
    apt_install "Slurm ($(missing_tools))" slurm-wlm munge ||
        fail "Slurm could not be installed (reason above)"
    [ -z "$(missing_tools)" ] || fail "apt-get installed slurm-wlm and munge, but these are still missing: $(missing_tools)"
    echo "installed slurm-wlm and munge in $((SECONDS - start)) s"
fi

# shellcheck source=SCRIPTDIR/slurm/one-node-cluster.sh
source scripts/slurm/one-node-cluster.sh
tmp=$(mktemp -d /tmp/beamflow-slurm.XXXXXX)
chmod 755 "$tmp" # munged wants every directory above its socket searchable
cleanup() {
    local status=$?
    cluster_down || status=1
    rm -rf "$tmp"
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

out=$tmp/out/placement-frame
logs=$out/logs

show_job_logs() {
    local f
    for f in "$logs"/*; do
        [ -f "$f" ] || continue
        echo "----- $f" >&2
        cat "$f" >&2
    done
    echo "----- jobs (scontrol show job)" >&2
    scontrol show job -o 2>&1 | grep -oE '^JobId=[^ ]*|(ArrayTaskId|JobName|JobState|Reason|ExitCode)=[^ ]*' |
        paste -sd ' ' | sed 's/ JobId=/\nJobId=/g' >&2 || true
    cluster_show_logs
}

# `JobState ExitCode` of every job (array tasks included) with this id, one per line.
job_states() {
    scontrol show job -o "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]* .*ExitCode=[0-9:]*' |
        sed -E 's/JobState=([A-Z_]*) .*ExitCode=([0-9:]*)/\1 \2/' || true
}

job_done() {
    case "$(job_states "$1")" in
        PENDING* | RUNNING* | CONFIGURING* | COMPLETING* | SUSPENDED* | REQUEUED* | "") return 1 ;;
        *) return 0 ;;
    esac
}

# Submits with submit-sweep.sh (extra arguments go to the array), waits for the merge job,
# checks that `expected_tasks` array tasks and the merge completed with exit code 0. Sets
# `array` and `merge` to the two job ids.
run_on_cluster() {
    local expected_tasks=$1 ids states submitted
    shift
    submitted=$SECONDS
    ids=$(scripts/slurm/submit-sweep.sh "$sweep" "$out" "$shards" "$@") ||
        fail "submit-sweep.sh could not submit"
    read -r array merge <<<"$ids"
    if ! cluster_wait_for "$job_timeout" job_done "$merge"; then
        show_job_logs
        fail "merge job $merge not finished after $job_timeout s (logs above)"
    fi
    echo "slurm: array job $array and merge job $merge done $((SECONDS - submitted)) s after submission"
    states=$(job_states "$array")
    if [ "$(grep -c '^COMPLETED 0:0$' <<<"$states")" -ne "$expected_tasks" ] ||
        [ "$(wc -l <<<"$states")" -ne "$expected_tasks" ] ||
        [ "$(job_states "$merge")" != "COMPLETED 0:0" ]; then
        show_job_logs
        fail "expected $expected_tasks array tasks and the merge COMPLETED with exit code 0, got:" \
            "array job $array: $(tr '\n' ',' <<<"$states") merge job $merge: $(job_states "$merge") (logs above)"
    fi
}

# The log of task k of the last array must show shard k/N and "C cases computed …, R reused".
check_task_log() {
    local k=$1 computed=$2 reused=$3 log
    log=$logs/placement-frame-${array}_$k.out
    grep -q "^shard $k/$shards of $sweep" "$log" || fail "array task $k: no 'shard $k/$shards' in $log"
    grep -qE "^$computed cases computed .*, $reused reused$" "$log" ||
        fail "array task $k: expected '$computed cases computed …, $reused reused' in $log, got:" \
            "$(grep 'cases computed' "$log" || cat "$log")"
}

# Removes the merged table, figure and best-case table, so that the next merge writes new ones.
remove_merged() { rm -f "$out.h5" "$out.net_power.png" "$out.net_power.svg" "$out.best.md"; }

compare_with_single() {
    local what=$1 ext
    for ext in h5 best.md net_power.png net_power.svg; do
        if ! cmp "$tmp/single/placement-frame.$ext" "$out.$ext"; then
            if [ "$ext" = h5 ]; then
                echo "h5dump difference, 17 digits (single-process < > Slurm merge):" >&2
                diff <(h5dump -m %.17g "$tmp/single/placement-frame.h5" | tail -n +2) \
                    <(h5dump -m %.17g "$out.h5" | tail -n +2) | head -n 40 >&2 || true
            fi
            fail "$what: $out.$ext differs from the single-process run's"
        fi
    done
    echo "slurm: $what: merged table, best-case table and figure equal the single run's byte for byte"
}

start=$SECONDS
cluster_up "$tmp/cluster" || fail "the one-node cluster did not start (logs above)"
up=$((SECONDS - start))

"$BEAMFLOW" sweep "$sweep" --out "$tmp/single/placement-frame.h5" >"$tmp/single.log" 2>&1 ||
    fail "the single-process run failed: $(cat "$tmp/single.log")"

# The array of 4 shards and the merge job, as docs/sweeps.md submits them.
run_on_cluster "$shards"
for k in $(seq 1 "$shards"); do
    check_task_log "$k" "$per_shard" 0
done
compare_with_single "job array of $shards shards + dependent merge"

# Resubmitting one lost shard alone (--array=3, still shard 3 of 4) recomputes it.
rm -f "$out/shard-3.h5"
remove_merged
run_on_cluster 1 --array=3
check_task_log 3 "$per_shard" 0
compare_with_single "shard 3 resubmitted alone (--array=3) + merge"

# Resubmitting the whole array recomputes nothing: every shard file is complete.
remove_merged
run_on_cluster "$shards"
for k in $(seq 1 "$shards"); do
    check_task_log "$k" 0 "$per_shard"
done
compare_with_single "whole array resubmitted (nothing recomputed) + merge"

echo "slurm check: 3 passed, 0 failed (cluster up in $up s, whole test on the cluster $((SECONDS - start)) s)"

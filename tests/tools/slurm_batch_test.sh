#!/usr/bin/env bash
# A batch through a real one-node Slurm cluster (tools/slurm_local.sh): two 20-frame smoke
# sequences, modes paper and improved, sequential once. Every job is submitted with sbatch
# through the profile eval/slurm/local, each one is COMPLETED in Slurm's job completion log
# (sacct -c) with the CPUs its execution asks for, and Table I and Table II equal those of
# the same batch run locally (sequential runs are byte-identical). Exits 77 (skipped) when
# the cluster cannot start here.
set -uo pipefail
SOURCE_DIR="${1:?usage: slurm_batch_test.sh SOURCE_DIR TOOLS_DIR}"
TOOLS_DIR="${2:?usage: slurm_batch_test.sh SOURCE_DIR TOOLS_DIR}"
SKIP=77
CLUSTER="${SOURCE_DIR}/tools/slurm_local.sh"

command -v snakemake >/dev/null || {
  echo "SKIP: snakemake is not installed (tools/install_deps.sh)"
  exit "${SKIP}"
}
if [ "$(id -u)" != 0 ] && ! { command -v sudo >/dev/null && sudo -n true 2>/dev/null; }; then
  echo "SKIP: starting the local Slurm cluster needs root or password-less sudo"
  exit "${SKIP}"
fi
started_here=0
if ! "${CLUSTER}" status >/dev/null 2>&1; then
  if ! "${CLUSTER}" start >/tmp/slurm_batch_test_start.$$ 2>&1; then
    echo "SKIP: the local Slurm cluster cannot start here (tools/slurm_local.sh start):"
    sed 's/^/    /' /tmp/slurm_batch_test_start.$$
    rm -f /tmp/slurm_batch_test_start.$$
    exit "${SKIP}"
  fi
  rm -f /tmp/slurm_batch_test_start.$$
  started_here=1
fi

source "${SOURCE_DIR}/tests/tools/check_helpers.sh"
# The cluster is stopped again when this test started it; the work folder goes.
trap '[ "${started_here}" = 1 ] && "${CLUSTER}" stop >/dev/null 2>&1; rm -rf "$WORK"' EXIT
# Snakemake's Slurm support reads $USER, which a CI container may not set.
export USER="${USER:-$(id -un)}"

cat >"$WORK/batch.yaml" <<EOF
tools: ${TOOLS_DIR}
out: slurm_out
sequences:
  - {preset: smoke, seed: 1, frames: 20}
  - {preset: smoke, seed: 2, frames: 20}
modes: [paper, improved]
executions: [sequential]
repeats: 1
EOF

check "the batch runs through Slurm" \
  "${SOURCE_DIR}/tools/ocg_batch" "$WORK/batch.yaml" --profile "${SOURCE_DIR}/eval/slurm/local"
cp "$WORK/out" "$WORK/slurm.log"
check "the same batch runs locally" \
  "${SOURCE_DIR}/tools/ocg_batch" "$WORK/batch.yaml" --out "$WORK/local_out" --cores 2

cp "$WORK/out" "$WORK/local.log"

# Every job of the batch (sequences, settings, runs, scores) went to Slurm: as many sbatch
# submissions as the same batch ran jobs locally (Snakemake's "Finished job" lines less the
# target "all", which has no command), and as many finished jobs as submissions.
JOBS=$(($(grep -c '^Finished job' "$WORK/local.log") - 1))
grep -o "submitted with SLURM jobid [0-9]*" "$WORK/slurm.log" | awk '{print $NF}' >"$WORK/ids"
check "$JOBS jobs submitted to Slurm (at least 2 sequences, 4 runs, 4 scores)" \
  test "$(wc -l <"$WORK/ids")" -eq "$JOBS" -a "$JOBS" -ge 10
check "no job ran outside Slurm" \
  test "$(grep -c '^Finished job' "$WORK/slurm.log")" -eq "$(($(wc -l <"$WORK/ids") + 1))"
sacct -c -P -n -o JobID,JobName,State,AllocCPUS -j "$(paste -sd, "$WORK/ids")" >"$WORK/sacct" 2>&1
check "sacct lists every job" test "$(wc -l <"$WORK/sacct")" -eq "$JOBS"
check "every job COMPLETED" bash -c "awk -F'|' '\$3 != \"COMPLETED\"' '$WORK/sacct' | (! grep -q .)"
check "4 run jobs, one CPU each (sequential)" \
  test "$(grep -c '|snakejob_run_[0-9]*|COMPLETED|1$' "$WORK/sacct")" -eq 4
for table in table_I.md table_II.md; do
  check "$table exists" test -s "$WORK/slurm_out/$table"
  check "$table equals the local batch's" cmp "$WORK/slurm_out/$table" "$WORK/local_out/$table"
done
check "Table I has the improved mode" grep -q improved "$WORK/slurm_out/table_I.md"
if [ "$failed" -ne 0 ]; then
  echo "--- Snakemake's output through Slurm:"
  tail -n 40 "$WORK/slurm.log"
  echo "--- sacct -c:"
  cat "$WORK/sacct"
fi
echo "$passed passed, $failed failed"
[ "$failed" -eq 0 ]

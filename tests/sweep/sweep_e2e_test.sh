#!/usr/bin/env bash
# End-to-end test of `pwsim sweep` on one engine:
#   sweep_e2e_test.sh local|slurm PWSIM SOURCE_DIR
# 1. a broken sweep file is refused by `plan` (file, line, field named) and nothing is submitted;
# 2. scenes/sweeps/speed_sweep.yaml: plan, submit, collect -> results.csv with 8 ok rows
#    (slurm: as one job array on a private single-node cluster, tests/sweep/slurm_cluster.sh);
# 3. a task killed mid-run (SIGKILL while it reads its input) is resubmitted and the collection
#    completes. Exit 77 (skip) when Slurm is not installed.
set -euo pipefail
engine=${1:?engine}
pwsim=$(realpath "${2:?pwsim}")
src=$(realpath "${3:?source dir}")
here="$src/tests/sweep"
work=$(mktemp -d /tmp/pwsim-sweep-e2e.XXXXXX)
cluster="$work/cluster"
cleanup() {
  local status=$?
  if [ "$engine" = slurm ] && [ -d "$cluster" ]; then "$here/slurm_cluster.sh" stop "$cluster" || true; fi
  if [ $status -eq 0 ]; then rm -rf "$work"; else echo "sweep_e2e_test: kept $work for inspection" >&2; fi
}
trap cleanup EXIT
fail() { echo "sweep_e2e_test ($engine): FAIL: $*" >&2; exit 1; }

submit_options=(--engine "$engine" --max-parallel 2)
if [ "$engine" = slurm ]; then
  status=0
  "$here/slurm_cluster.sh" start "$cluster" || status=$?
  if [ $status -eq 77 ]; then echo "sweep_e2e_test: SKIP: no Slurm here"; exit 77; fi
  [ $status -eq 0 ] || fail "the private Slurm cluster did not start"
  # shellcheck disable=SC1091
  . "$cluster/env"
  submit_options+=(--poll-s 0.1)
fi

# 1. a broken sweep file: refused at plan time, no manifest, submit refuses, nothing queued
cat > "$work/broken.yaml" <<YAML
format: pwsim-sweep/1
name: broken
command: [run]
inputs: {scene: $src/scenes/speed_cushion.yaml}
arguments: ["{scene}", --no-video, --out, "{out}"]
grid:
  scene.drvie.speed_mps: [0.5, 1.0]
gather:
  peak_heave_m: {file: summary.json, path: peak_heave.excursion_m}
YAML
if "$pwsim" sweep plan "$work/broken.yaml" --out "$work/broken" > "$work/broken.txt" 2>&1; then
  fail "a sweep file with a misspelt key was planned"
fi
grep -q "broken.yaml:7: field 'grid.scene.drvie.speed_mps'" "$work/broken.txt" ||
  fail "the error does not name file, line and field: $(cat "$work/broken.txt")"
[ ! -e "$work/broken/manifest.json" ] || fail "a refused sweep left a manifest"
if "$pwsim" sweep submit "$work/broken" "${submit_options[@]}" > /dev/null 2>&1; then
  fail "submit ran an unplanned sweep"
fi
if [ "$engine" = slurm ]; then
  [ -z "$(squeue --noheader)" ] || fail "something was queued for a refused sweep"
  [ ! -s "$cluster/jobcomp.txt" ] || fail "a job ran for a refused sweep"
fi

# 2. the speed sweep: 8 tasks, one job array
"$pwsim" sweep plan "$src/scenes/sweeps/speed_sweep.yaml" --out "$work/speed" > /dev/null
"$pwsim" sweep submit "$work/speed" "${submit_options[@]}" > "$work/speed_submit.txt" ||
  fail "submit of the speed sweep: $(cat "$work/speed_submit.txt")"
"$pwsim" sweep collect "$work/speed" > "$work/speed_collect.txt" ||
  fail "collect of the speed sweep: $(cat "$work/speed_collect.txt")"
rows=$(tail -n +2 "$work/speed/results.csv" | wc -l)
ok_rows=$(tail -n +2 "$work/speed/results.csv" | awk -F, '$3 == "ok" && $6 != "" && $7 != ""' | wc -l)
[ "$rows" -eq 8 ] && [ "$ok_rows" -eq 8 ] || fail "results.csv: $rows rows, $ok_rows ok with both fields"
[ -s "$work/speed/plots/scene_drive_speed_mps.png" ] || fail "no plot of speed against the fields"
# a task without a result makes collect fail and list it; submit runs only that one again
mv "$work/speed/tasks/5/result.json" "$work/result5.json"
if "$pwsim" sweep collect "$work/speed" > "$work/collect_missing.txt"; then fail "collect passed with task 5 missing"; fi
grep -q "^task 5 (.*): missing" "$work/speed/missing.txt" || fail "missing.txt does not list task 5"
if [ "$engine" = local ]; then
  "$pwsim" sweep submit "$work/speed" "${submit_options[@]}" > "$work/resume.txt" || fail "resume: $(cat "$work/resume.txt")"
  grep -q "1 of 8 tasks to run" "$work/resume.txt" || fail "resume ran more than task 5: $(cat "$work/resume.txt")"
  [ -e "$work/speed/tasks/5/attempt-2.log" ] && [ ! -e "$work/speed/tasks/4/attempt-2.log" ] || fail "resume ran the wrong tasks"
  "$pwsim" sweep collect "$work/speed" > /dev/null || fail "collect after resume"
else
  mv "$work/result5.json" "$work/speed/tasks/5/result.json"
fi
if [ "$engine" = slurm ]; then
  [ "$(wc -l < "$work/speed/slurm/jobs.txt")" -eq 1 ] || fail "more than one sbatch: $(cat "$work/speed/slurm/jobs.txt")"
  array_job=$(cut -d' ' -f1 "$work/speed/slurm/jobs.txt")
  # the completion log of the cluster: 8 completed tasks of that one array job
  done_tasks=$(grep -c "JobState=COMPLETED .*ArrayJobId=$array_job ArrayTaskId=" "$cluster/jobcomp.txt" || true)
  [ "$done_tasks" -eq 8 ] || fail "jobcomp.txt shows $done_tasks completed tasks of array $array_job"
fi

# 3. a task killed mid-run is resubmitted: task 1 reads its scene from a FIFO
mkfifo "$work/scene.fifo"
sed -e "s|\.\./assets/|$src/assets/|" -e "s|^platform: platforms/|platform: $src/scenes/platforms/|" \
  "$src/scenes/speed_cushion.yaml" > "$work/scene.yaml"
cat > "$work/kill.yaml" <<YAML
format: pwsim-sweep/1
name: kill_and_retry
command: [run]
arguments: ["{scene_file}", --no-video, --decimate, "{decimate}", --out, "{out}"]
list:
  - {scene_file: $work/scene.yaml, decimate: 50}
  - {scene_file: $work/scene.fifo, decimate: 50}
gather:
  peak_pitch_rad: {file: summary.json, path: peak_pitch.excursion_rad}
retries: 2
YAML
"$pwsim" sweep plan "$work/kill.yaml" --out "$work/kill" > /dev/null
timeout 120 "$pwsim" sweep submit "$work/kill" "${submit_options[@]}" > "$work/kill_submit.txt" 2>&1 &
submit_pid=$!
killed=$(python3 "$here/kill_fifo_reader.py" "$work/scene.fifo" "$work/scene.yaml") ||
  { kill "$submit_pid" 2>/dev/null || true; fail "could not kill and feed the FIFO task"; }
wait "$submit_pid" || fail "submit after the kill: $(cat "$work/kill_submit.txt")"
"$pwsim" sweep collect "$work/kill" > "$work/kill_collect.txt" || fail "collect: $(cat "$work/kill_collect.txt")"
grep -q "attempt 1" "$work/kill/tasks/1/attempt-1.log" || fail "no first attempt log"
[ -e "$work/kill/tasks/1/attempt-2.log" ] || fail "task 1 was not resubmitted"
task1=$(awk -F, '$1 == 1' "$work/kill/results.csv")
case "$task1" in 1,*,ok,2,*) ;; *) fail "task 1 in results.csv: $task1 (expected ok after 2 attempts)";; esac
[ "$(awk -F, 'NR > 1 && $3 == "ok"' "$work/kill/results.csv" | wc -l)" -eq 2 ] || fail "not both tasks ok"
if [ "$engine" = slurm ]; then
  [ "$(wc -l < "$work/kill/slurm/jobs.txt")" -eq 2 ] || fail "expected the array and one resubmission: $(cat "$work/kill/slurm/jobs.txt")"
  sed -n 2p "$work/kill/slurm/jobs.txt" | grep -qE " array=1(%|$)" || fail "the resubmission is not task 1 alone"
fi
echo "sweep_e2e_test ($engine): ok (killed pid $killed; task 1 resubmitted and completed)"

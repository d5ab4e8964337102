#!/usr/bin/env bash
# tests/jobs/job_scripts_test.sh CASE      (ctest -L jobs runs every test_* function as jobs_CASE)
# Runs jobs/slurm/texsim.sbatch and jobs/pbs/texsim.pbs with fake srun, mpirun, scontrol, qsub
# and qstat on PATH (tests/jobs/fake_command.sh) and checks what they decide: which texsim command
# line starts, whether the job is requeued or its successor submitted, and with what.
set -euo pipefail
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/bin" "$work/calls"
for command in srun mpirun scontrol qsub qstat; do
  ln -s "$source_dir/tests/jobs/fake_command.sh" "$work/bin/$command"
done
export PATH="$work/bin:$PATH" FAKE_DIR=$work FAKE_QSTAT=$work/qstat
unset TEXSIM_MAX_REQUEUES TEXSIM_ARGS TEXSIM_RESUBMITS TEXSIM_WARNING_SECONDS SLURM_RESTART_COUNT
out=$work/out

# `qstat -f` of the running PBS job, as PBS Pro prints it: long values wrap onto tab-led lines.
cat >"$work/qstat" <<'QSTAT'
Job Id: 1234.pbs01
    Job_Name = spots
    Job_Owner = ada@login01
    job_state = R
    queue = workq
    server = pbs01
    Account_Name = proj42
    Resource_List.mem = 200gb
    Resource_List.mpiprocs = 64
    Resource_List.ncpus = 64
    Resource_List.nodect = 2
    Resource_List.place = scatter:excl
    Resource_List.select = 2:ncpus=32:mpiprocs=32:mem=100gb:model=skylake+1:ncp
	us=4:mpiprocs=1
    Resource_List.walltime = 04:00:00
    Variable_List = PBS_O_HOME=/home/ada,PBS_O_LANG=C.UTF-8,PBS_O_LOGNAME=ada,
	PBS_O_WORKDIR=/home/ada/texsim,CONFIG=config.yaml
    project = climate
QSTAT

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Runs the SCHEDULER's job script after RESUBMITS earlier attempts, passing further texsim
# options; sets status to its exit code and log to its output.
run_job() {
  local scheduler=$1 resubmits=$2
  shift 2
  rm -f "$work"/calls/*
  status=0
  case $scheduler in
    slurm)
      log=$(SLURM_SUBMIT_DIR=$source_dir SLURM_JOB_ID=777 SLURM_RESTART_COUNT=$resubmits \
        TEXSIM=texsim bash "$source_dir/jobs/slurm/texsim.sbatch" config.yaml "$out" "$@" 2>&1) ||
        status=$?
      ;;
    pbs)
      log=$(PBS_O_WORKDIR=$source_dir PBS_JOBID=1234.pbs01 TEXSIM_RESUBMITS=$resubmits \
        CONFIG=config.yaml OUTPUT_DIR=$out TEXSIM=texsim TEXSIM_ARGS="$*" \
        bash "$source_dir/jobs/pbs/texsim.pbs" 2>&1) || status=$?
      ;;
  esac
}

launcher_of() { if [ "$1" = slurm ]; then echo srun; else echo mpirun; fi; }
resubmitter_of() { if [ "$1" = slurm ]; then echo scontrol; else echo qsub; fi; }

# The arguments of the one call to COMMAND, one per line; fails unless there was exactly one.
arguments_of() {
  local files=("$work"/calls/*-"$1")
  if [ ! -e "${files[0]}" ] || [ ${#files[@]} -ne 1 ]; then
    fail "expected one call to $1, found: $(ls "$work/calls")"$'\n'"$log"
  fi
  cat "${files[0]}"
}

# Fails unless COMMAND was called once with exactly the arguments ARGS...
expect_call() {
  local command=$1
  shift
  local expected actual
  expected=$(printf '%s\n' "$@")
  actual=$(arguments_of "$command")
  [ "$actual" = "$expected" ] ||
    fail "$command called with"$'\n'"$actual"$'\n'"expected"$'\n'"$expected"$'\n'"$log"
}

expect_no_call() {
  local files=("$work"/calls/*-"$1")
  [ ! -e "${files[0]}" ] || fail "$1 was called:"$'\n'"$(cat "${files[0]}")"$'\n'"$log"
}

expect_status() {
  [ "$status" -eq "$1" ] || fail "the job exited with $status, expected $1"$'\n'"$log"
}

expect_log() {
  [[ $log == *"$1"* ]] || fail "the job's output lacks '$1':"$'\n'"$log"
}

# The arguments of the successor the PBS job submits, one per line: qsub with the requests in
# $work/qstat, TEXSIM_ARGS as given and the resubmission count and bound.
pbs_successor_arguments() {
  local resubmits=$1 max=$2 texsim_args=$3
  printf '%s\n' -W depend=afterany:1234.pbs01 -N spots -q workq -A proj42 -l place=scatter:excl \
    -l select=2:ncpus=32:mpiprocs=32:mem=100gb:model=skylake+1:ncpus=4:mpiprocs=1 \
    -l walltime=04:00:00 -P climate \
    -v "CONFIG=config.yaml,OUTPUT_DIR=$out,TEXSIM=texsim,TEXSIM_ARGS=$texsim_args,TEXSIM_RESUBMITS=$resubmits,TEXSIM_MAX_REQUEUES=$max,TEXSIM_WARNING_SECONDS=300" \
    jobs/pbs/texsim.pbs
}

expect_resubmission() {
  local scheduler=$1 resubmits=$2 max=$3
  if [ "$scheduler" = slurm ]; then
    expect_call scontrol requeue 777
  else
    local -a expected
    mapfile -t expected < <(pbs_successor_arguments $((resubmits + 1)) "$max" "")
    expect_call qsub "${expected[@]}"
  fi
}

test_resubmits_when_texsim_checkpointed() {
  export FAKE_TEXSIM_EXIT=3
  for scheduler in slurm pbs; do
    for resubmits in 0 9; do
      run_job $scheduler $resubmits
      expect_status 3
      expect_resubmission $scheduler $resubmits 10
    done
  done
}

test_stops_resubmitting_at_the_bound() {
  export FAKE_TEXSIM_EXIT=3
  for scheduler in slurm pbs; do
    run_job $scheduler 10
    expect_status 3
    expect_no_call "$(resubmitter_of $scheduler)"
    expect_log "TEXSIM_MAX_REQUEUES=10"
    TEXSIM_MAX_REQUEUES=2 run_job $scheduler 1
    expect_resubmission $scheduler 1 2
    TEXSIM_MAX_REQUEUES=2 run_job $scheduler 2
    expect_no_call "$(resubmitter_of $scheduler)"
    TEXSIM_MAX_REQUEUES=0 run_job $scheduler 0
    expect_status 3
    expect_no_call "$(resubmitter_of $scheduler)"
  done
}

test_other_exit_codes_end_the_job_with_that_code() {
  for scheduler in slurm pbs; do
    for code in 0 1 2 137; do
      FAKE_TEXSIM_EXIT=$code run_job $scheduler 0
      expect_status $code
      expect_no_call "$(resubmitter_of $scheduler)"
    done
  done
}

test_refuses_a_malformed_bound() {
  for scheduler in slurm pbs; do
    TEXSIM_MAX_REQUEUES=ten run_job $scheduler 0
    expect_status 2
    expect_log "TEXSIM_MAX_REQUEUES must be a non-negative integer, got 'ten'"
    expect_no_call "$(launcher_of $scheduler)"
  done
}

test_restarts_only_from_a_checkpoint() {
  for scheduler in slurm pbs; do
    local launcher
    launcher=$(launcher_of $scheduler)
    rm -rf "$out"
    run_job $scheduler 0
    expect_call "$launcher" texsim config.yaml --set output.dir="$out"

    # An attempt stopped before its first checkpoint left frames: the next one starts afresh.
    mkdir -p "$out/checkpoints"
    touch "$out/fem_rd.pvd" "$out/checkpoints/.step_000000020.h5.tmp"
    run_job $scheduler 1
    expect_call "$launcher" texsim config.yaml --set output.dir="$out" --set output.overwrite=true
    # ... but a first attempt never overwrites what it finds (texsim refuses another run).
    run_job $scheduler 0
    expect_call "$launcher" texsim config.yaml --set output.dir="$out"

    touch "$out/checkpoints/step_000000010.h5"
    for resubmits in 0 1; do
      run_job $scheduler $resubmits
      expect_call "$launcher" texsim config.yaml --set output.dir="$out" --restart latest
    done

    touch "$out/summary.json"
    run_job $scheduler 1
    expect_call "$launcher" texsim config.yaml --set output.dir="$out"
  done
}

test_passes_texsim_options_through() {
  rm -rf "$out"
  run_job slurm 0 --set seed=3 --set 'synthesis.dims=[8,8,8]' -ksp_type cg
  expect_call srun texsim config.yaml --set output.dir="$out" \
    --set seed=3 --set 'synthesis.dims=[8,8,8]' -ksp_type cg
  mkdir -p "$out/checkpoints" && touch "$out/checkpoints/step_000000010.h5"
  FAKE_TEXSIM_EXIT=3 run_job pbs 0 --set seed=3 --set 'synthesis.dims=[8,8,8]' -ksp_type cg
  expect_call mpirun texsim config.yaml --set output.dir="$out" --restart latest \
    --set seed=3 --set 'synthesis.dims=[8,8,8]' -ksp_type cg
}

test_pbs_successor_has_the_parent_resources_and_options() {
  export FAKE_TEXSIM_EXIT=3
  local texsim_args="--set seed=3 --set synthesis.dims=[8,8,8]"
  run_job pbs 0 "$texsim_args"
  # TEXSIM_ARGS holds commas, qsub's separator: it travels quoted.
  local -a expected
  mapfile -t expected < <(pbs_successor_arguments 1 10 "'$texsim_args'")
  expect_call qsub "${expected[@]}"
}

test_pbs_successor_without_select_keeps_the_node_request() {
  export FAKE_TEXSIM_EXIT=3
  cat >"$work/qstat" <<'QSTAT'
Job Id: 1234.pbs01
    Job_Name = texsim
    queue = batch
    Resource_List.ncpus = 64
    Resource_List.nodect = 2
    Resource_List.nodes = 2:ppn=32
    Resource_List.walltime = 12:00:00
QSTAT
  run_job pbs 0
  expect_call qsub -W depend=afterany:1234.pbs01 -N texsim -q batch \
    -l ncpus=64 -l nodes=2:ppn=32 -l walltime=12:00:00 \
    -v "CONFIG=config.yaml,OUTPUT_DIR=$out,TEXSIM=texsim,TEXSIM_ARGS=,TEXSIM_RESUBMITS=1,TEXSIM_MAX_REQUEUES=10,TEXSIM_WARNING_SECONDS=300" \
    jobs/pbs/texsim.pbs
}

# SIGNAL sent to the batch shell while the fake launcher runs must reach the launcher as USR1.
expect_forwarded() {
  local scheduler=$1 signal=$2
  rm -f "$work"/calls/* "$work/signal" "$work/launcher_started"
  mkdir -p "$out/checkpoints" && touch "$out/checkpoints/step_000000010.h5"
  export FAKE_AWAIT_SIGNAL=1 FAKE_TEXSIM_EXIT=3
  if [ "$scheduler" = slurm ]; then
    SLURM_SUBMIT_DIR=$source_dir SLURM_JOB_ID=777 TEXSIM=texsim \
      bash "$source_dir/jobs/slurm/texsim.sbatch" config.yaml "$out" >"$work/log" 2>&1 &
  else
    PBS_O_WORKDIR=$source_dir PBS_JOBID=1234.pbs01 CONFIG=config.yaml OUTPUT_DIR=$out \
      TEXSIM=texsim bash "$source_dir/jobs/pbs/texsim.pbs" >"$work/log" 2>&1 &
  fi
  local job=$!
  until [ -e "$work/launcher_started" ]; do
    kill -0 "$job" 2>/dev/null || fail "the job ended before its launcher started: $(cat "$work/log")"
    sleep 0.1
  done
  kill -s "$signal" "$job"
  status=0
  wait "$job" || status=$?
  log=$(cat "$work/log")
  [ "$(cat "$work/signal")" = USR1 ] ||
    fail "$scheduler: $signal to the batch shell reached $(launcher_of "$scheduler") as $(cat "$work/signal")"
  expect_status 3
  expect_resubmission "$scheduler" 0 10
  unset FAKE_AWAIT_SIGNAL
}

test_slurm_passes_usr1_and_term_to_srun() {
  expect_forwarded slurm USR1
  expect_forwarded slurm TERM
}

test_pbs_passes_usr1_and_term_to_mpirun() {
  expect_forwarded pbs USR1
  expect_forwarded pbs TERM
}

test_slurm_asks_for_the_warning_signal_in_the_batch_shell() {
  grep -qE '^#SBATCH --signal=B:USR1@[0-9]+$' "$source_dir/jobs/slurm/texsim.sbatch" ||
    fail "jobs/slurm/texsim.sbatch does not ask for USR1 before the time limit"
  grep -qx '#SBATCH --requeue' "$source_dir/jobs/slurm/texsim.sbatch" ||
    fail "jobs/slurm/texsim.sbatch is not requeueable"
}

test_pbs_warns_texsim_before_the_walltime() {
  # A walltime of 5 min 1 s and the default 300 s warning: USR1 comes after one second.
  sed -i 's/Resource_List.walltime = 04:00:00/Resource_List.walltime = 00:05:01/' "$work/qstat"
  rm -f "$work/signal"
  FAKE_AWAIT_SIGNAL=1 FAKE_TEXSIM_EXIT=3 run_job pbs 0
  [ "$(cat "$work/signal")" = USR1 ] || fail "mpirun got no USR1 before the walltime"$'\n'"$log"
  expect_status 3
  arguments_of qsub | grep -qx "walltime=00:05:01" || fail "successor lost the walltime"
}

case=${1:?usage: job_scripts_test.sh CASE}
declare -F "test_$case" >/dev/null || fail "no test case '$case'"
"test_$case"
echo "PASS: $case"

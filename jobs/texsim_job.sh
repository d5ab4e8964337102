# source jobs/texsim_job.sh      (by jobs/slurm/texsim.sbatch and jobs/pbs/texsim.pbs)
# What a batch job around texsim decides, the same under every scheduler:
#   texsim_restart_args DIR RESUBMITS     how texsim starts: from the latest checkpoint or afresh
#   texsim_run LAUNCHER ARGS...           runs texsim, passing the scheduler's warning signal on
#   texsim_should_resubmit STATUS RESUBMITS   whether the job queues its continuation
# texsim's exit codes: 0 finished, 1 internal error, 2 bad input (one message names the key or
# file), 3 checkpointed on SIGTERM/SIGUSR1: resubmit to continue. Only 3 leads to a resubmission,
# at most TEXSIM_MAX_REQUEUES times (default 10).
# shellcheck shell=bash disable=SC2034  # restart_args and texsim_status are the job scripts' to read

readonly texsim_checkpointed=3

# Ends the job with exit code 2 unless $2 (the value of $1) is a non-negative integer.
texsim_require_count() {
  [[ $2 =~ ^[0-9]+$ ]] && return 0
  echo "texsim job: $1 must be a non-negative integer, got '$2'" >&2
  exit 2
}

texsim_max_resubmits=${TEXSIM_MAX_REQUEUES:-10}
texsim_require_count TEXSIM_MAX_REQUEUES "$texsim_max_resubmits"

# Sets the array restart_args for a job writing to DIR that has been resubmitted RESUBMITS times.
texsim_restart_args() {
  local dir=$1 resubmits=$2
  restart_args=()
  if [ -f "$dir/summary.json" ]; then
    echo "texsim job: $dir holds a finished run (summary.json); texsim will not overwrite it"
  elif compgen -G "$dir/checkpoints/step_*.h5" >/dev/null; then
    restart_args=(--restart latest)
    echo "texsim job: restarting from the latest checkpoint in $dir/checkpoints"
  elif [ "$resubmits" -gt 0 ] && [ -d "$dir" ]; then
    # An earlier attempt of this job was stopped before its first checkpoint: its frames are ours.
    restart_args=(--set output.overwrite=true)
    echo "texsim job: the previous attempt left no checkpoint in $dir; starting afresh"
  else
    echo "texsim job: starting afresh in $dir"
  fi
}

# Runs "$@" (srun or mpirun with texsim's command line) and sets texsim_status to its exit code.
# USR1 or TERM sent to this batch shell (the scheduler's warning before the time limit) is passed
# to the launcher as USR1, which srun and mpirun forward to every rank (mpirun kills its ranks on
# TERM instead); texsim then finishes its step, writes a checkpoint and exits with 3.
texsim_run() {
  texsim_launcher=
  texsim_signalled=0
  trap 'texsim_forward_warning USR1' USR1
  trap 'texsim_forward_warning TERM' TERM
  "$@" &
  texsim_launcher=$!
  texsim_status=
  local status
  while :; do
    texsim_signalled=0
    status=0
    wait "$texsim_launcher" || status=$?
    # 127 after a signal: the previous wait had already collected the launcher's exit code.
    if [ "$status" -eq 127 ] && [ -n "$texsim_status" ]; then
      break
    fi
    texsim_status=$status
    # A trapped signal makes wait return early: wait again until the launcher itself has ended.
    [ "$texsim_signalled" -eq 1 ] || break
  done
  echo "texsim job: texsim exited with $texsim_status ($(texsim_exit_meaning "$texsim_status"))"
}

texsim_forward_warning() {
  texsim_signalled=1
  echo "texsim job: $1 received; asking texsim to checkpoint and stop"
  if [ -n "$texsim_launcher" ]; then
    kill -s USR1 "$texsim_launcher" 2>/dev/null || true
  fi
}

texsim_exit_meaning() {
  case $1 in
    0) echo "finished" ;;
    1) echo "internal error" ;;
    2) echo "bad input: see the message above" ;;
    3) echo "checkpointed on a signal" ;;
    *) if [ "$1" -gt 128 ]; then echo "killed by signal $(($1 - 128))"; else echo "failed"; fi ;;
  esac
}

# Succeeds when a job whose texsim exited with STATUS, and which has been resubmitted RESUBMITS
# times already, should queue its continuation.
texsim_should_resubmit() {
  local status=$1 resubmits=$2 max=$texsim_max_resubmits
  if [ "$status" -ne "$texsim_checkpointed" ]; then
    echo "texsim job: not resubmitting (only exit code $texsim_checkpointed resubmits)"
    return 1
  fi
  if [ "$resubmits" -ge "$max" ]; then
    echo "texsim job: checkpointed, but the job has been resubmitted $resubmits times" \
      "(TEXSIM_MAX_REQUEUES=$max); submit it again to continue from the checkpoint"
    return 1
  fi
  echo "texsim job: checkpointed; resubmitting ($((resubmits + 1)) of at most $max)"
}

#!/usr/bin/env bash
# Stands in for srun, mpirun, scontrol, qsub and qstat (job_scripts_test.sh links it under those
# names). Each call is recorded as $FAKE_DIR/calls/<n>-<name>, one argument per line; then:
#   srun, mpirun  exit with $FAKE_TEXSIM_EXIT (default 0), as texsim would. With FAKE_AWAIT_SIGNAL=1
#                 they first touch $FAKE_DIR/launcher_started, wait for USR1 or TERM and write its
#                 name to $FAKE_DIR/signal.
#   qstat         prints $FAKE_QSTAT (the `qstat -f` text of the running job)
#   qsub          prints a job id;   scontrol: nothing
set -euo pipefail
name=$(basename "$0")
calls=("$FAKE_DIR"/calls/*)
[ -e "${calls[0]}" ] || calls=()
printf '%s\n' "$@" >"$FAKE_DIR/calls/$(printf %03d ${#calls[@]})-$name"

case $name in
  srun | mpirun)
    if [ "${FAKE_AWAIT_SIGNAL:-0}" = 1 ]; then
      trap 'echo USR1 >"$FAKE_DIR/signal"' USR1
      trap 'echo TERM >"$FAKE_DIR/signal"' TERM
      touch "$FAKE_DIR/launcher_started"
      until [ -s "$FAKE_DIR/signal" ]; do
        sleep 0.1
      done
    fi
    exit "${FAKE_TEXSIM_EXIT:-0}"
    ;;
  qstat) cat "$FAKE_QSTAT" ;;
  qsub) echo "5678.pbs01" ;;
esac

# Sourced by the job templates: sets restart_args to "--restart latest" when OUTPUT_DIR already
# holds a checkpoint (the job was requeued or chained), else to "--set output.overwrite=false" so a
# finished run in OUTPUT_DIR is never overwritten by accident.
# shellcheck shell=bash
if compgen -G "${OUTPUT_DIR}/checkpoints/step_*.h5" >/dev/null; then
  restart_args=(--restart latest)
  echo "texsim job: restarting from the latest checkpoint in ${OUTPUT_DIR}/checkpoints"
else
  restart_args=(--set output.overwrite=false)
fi

# Sourced by the job templates: sets restart_args for texsim from what OUTPUT_DIR holds.
#   a checkpoint                      -> --restart latest (the job was requeued or chained)
#   no checkpoint and no summary.json -> start afresh over the interrupted attempt
#   a finished run (summary.json)     -> nothing: texsim refuses to overwrite it
# shellcheck shell=bash
if compgen -G "${OUTPUT_DIR}/checkpoints/step_*.h5" >/dev/null; then
  restart_args=(--restart latest)
  echo "texsim job: restarting from the latest checkpoint in ${OUTPUT_DIR}/checkpoints"
elif [ -d "${OUTPUT_DIR}" ] && [ ! -f "${OUTPUT_DIR}/summary.json" ]; then
  restart_args=(--set output.overwrite=true)
  echo "texsim job: no checkpoint in ${OUTPUT_DIR} yet, starting afresh"
else
  restart_args=()
fi

#!/usr/bin/env bash
# Every #include "<layer>/..." in src/ names a layer at or below the including file's own
# (docs/ARCHITECTURE.md: core -> rd | par -> vtk -> geom | img | vol -> io -> pipelines -> app), and
# no pipeline includes another pipeline's files (what two pipelines share belongs to a lower
# layer). Prints each offending line; exits 1 if there is one.
set -euo pipefail
src=${1:?usage: check_layers.sh SRC_DIR}
declare -A allowed=(
  [core]="core"
  [rd]="core rd"
  [par]="core par"
  [vtk]="core par vtk"
  [geom]="core par vtk geom"
  [img]="core par vtk img"
  [vol]="core par vtk img vol"
  [io]="core par vtk io"
  [pipelines]="core rd par vtk geom img vol io pipelines"
  [app]="core rd par vtk geom img vol io pipelines app texsim"
)
status=0
# Bash's own pattern matching only: a process per include line took 31 s of a quiet 2-core machine
# (over the 60 s limit beside other tests).
include='^([^:]+):[0-9]+:#include "([a-z_]+)/([^"]+)"'
for layer in "${!allowed[@]}"; do
  [ -d "$src/$layer" ] || continue
  while IFS= read -r line; do
    [[ $line =~ $include ]] || continue
    file=${BASH_REMATCH[1]} target=${BASH_REMATCH[2]} rest=${BASH_REMATCH[3]}
    if [[ " ${allowed[$layer]} " != *" $target "* ]]; then
      echo "layer $layer includes $target: $line"
      status=1
    fi
    # A pipeline's files include only their own folder's files and pipelines/pipeline.hpp.
    if [ "$layer" = pipelines ] && [ "$target" = pipelines ]; then
      own=${file#"$src/pipelines/"}
      own=${own%%/*}
      if [[ "$rest" == */* && "${rest%%/*}" != "$own" ]]; then
        echo "pipeline $own includes another pipeline's file: $line"
        status=1
      fi
    fi
  done < <(grep -rnE '^#include "[a-z_]+/' "$src/$layer" || true)
done
exit $status

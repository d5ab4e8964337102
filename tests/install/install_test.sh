#!/usr/bin/env bash
# tests/install/install_test.sh CASE BUILD_DIR   (ctest -L install runs every test_* as install_CASE)
# texsim installed as a site installs it: `cmake --install` into a temporary prefix, run from a
# directory outside the source tree with data only where TEXSIM_DATA says; the Debian package
# unpacked into a fresh dpkg root; the Lmod module loaded in a new bash.
set -euo pipefail
case_name=${1:?usage: install_test.sh CASE BUILD_DIR}
build_dir=$(realpath "${2:?usage: install_test.sh CASE BUILD_DIR}")
source_dir=$(cd "$(dirname "$0")/../.." && pwd)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
unset TEXSIM TEXSIM_DATA TEXSIM_HOME
mpirun=(mpirun --allow-run-as-root --oversubscribe -x OMP_NUM_THREADS=1)

fail() {
  echo "FAIL: $*" >&2
  exit 1
}

# Installs the build into $prefix.
install_prefix() {
  prefix=$work/prefix
  cmake --install "$build_dir" --prefix "$prefix" >"$work/install.log" ||
    fail "cmake --install: $(tail -5 "$work/install.log")"
}

test_installed_texsim_runs_outside_the_source_tree() {
  install_prefix
  for file in bin/texsim bin/texsim-render bin/texsim-fetch-data share/texsim/config/fem_rd/smoke.yaml \
    share/texsim/jobs/texsim_job.sh share/texsim/jobs/slurm/texsim.sbatch \
    share/texsim/jobs/pbs/texsim.pbs share/doc/texsim/README.md share/doc/texsim/fem_rd.md \
    share/texsim/modulefiles/texsim/*.lua; do
    compgen -G "$prefix/$file" >/dev/null || fail "$prefix/$file was not installed"
  done
  mkdir "$work/run"
  cd "$work/run" # no config/, data/ or build/ here
  export PATH="$prefix/bin:$PATH"
  local version
  version=$(texsim --version) || fail "texsim --version failed"
  [[ $version == *"prefix: $prefix"* ]] || fail "texsim --version does not name the prefix: $version"
  texsim validate --quiet "$prefix/share/texsim/config/fem_rd/smoke.yaml" ||
    fail "the installed smoke config does not validate"
  "${mpirun[@]}" -n 2 texsim --quiet "$prefix/share/texsim/config/fem_rd/smoke.yaml" \
    --set output.dir=out --set fem_rd.time.steps=20 >"$work/run.log" 2>&1 ||
    fail "fem_rd smoke run at -n 2: $(tail -5 "$work/run.log")"
  [ -f out/fem_rd.pvd ] && find out -name '*.pvtu' | grep -q . ||
    fail "the smoke run wrote no ParaView files: $(find out | head)"
  # A config naming data reads it from TEXSIM_DATA: an empty data directory is named in the error.
  mkdir "$work/empty_data"
  local status=0 message
  message=$(TEXSIM_DATA=$work/empty_data texsim validate \
    "$prefix/share/texsim/config/fem_rd/bunny.yaml" 2>&1) || status=$?
  [ "$status" -eq 2 ] || fail "bunny.yaml without its data: exit $status, expected 2: $message"
  [[ $message == *"$work/empty_data/meshes/bunny00.off"* ]] ||
    fail "the error does not name the file under TEXSIM_DATA: $message"
}

test_installed_job_template_runs_the_installed_binary() {
  install_prefix
  mkdir -p "$work/bin" "$work/calls" "$work/submit"
  ln -s "$source_dir/tests/jobs/fake_command.sh" "$work/bin/srun"
  ln -s "$source_dir/tests/jobs/fake_command.sh" "$work/bin/scontrol"
  local status=0
  (cd "$work/submit" && PATH="$work/bin:$PATH" FAKE_DIR=$work SLURM_SUBMIT_DIR=$work/submit \
    SLURM_JOB_ID=7 SLURM_RESTART_COUNT=0 \
    bash "$prefix/share/texsim/jobs/slurm/texsim.sbatch" config.yaml out) >"$work/job.log" 2>&1 ||
    status=$?
  [ "$status" -eq 0 ] || fail "the installed Slurm template exited $status: $(cat "$work/job.log")"
  local call
  call=$(head -1 "$work"/calls/*-srun)
  [ "$call" = "$prefix/bin/texsim" ] || fail "srun ran '$call', expected $prefix/bin/texsim"
}

test_debian_package_installs_into_a_fresh_root() {
  local deb
  deb=$("$source_dir/scripts/package" --build-dir "$build_dir" --output-dir "$work/deb" \
    2>"$work/package.log") || fail "scripts/package: $(tail -5 "$work/package.log")"
  [[ $(basename "$deb") =~ ^texsim_[0-9.]+_amd64\.deb$ ]] || fail "unexpected package name $deb"
  local depends
  depends=$(dpkg-deb -f "$deb" Depends)
  for library in libpetsc-real libhdf5-openmpi libvtk9 libopenvdb libopenmpi openmpi-bin; do
    [[ $depends == *"$library"* ]] || fail "Depends lacks $library: $depends"
  done
  local root=$work/root
  mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
  touch "$root/var/lib/dpkg/status" "$root/var/lib/dpkg/available"
  # The fresh root has none of the dependencies; this machine has them, for ldd below.
  dpkg --root="$root" --force-depends --log=/dev/null -i "$deb" >"$work/dpkg.log" 2>&1 ||
    fail "dpkg -i: $(tail -5 "$work/dpkg.log")"
  [[ $(dpkg --root="$root" -s texsim) == *"Depends: $depends"* ]] ||
    fail "dpkg -s does not show the declared dependencies"
  local missing
  missing=$(ldd "$root/usr/bin/texsim" | grep "not found" || true)
  [ -z "$missing" ] || fail "the installed binary's libraries are missing: $missing"
  [ -f "$root/usr/share/texsim/config/default.yaml" ] || fail "the package has no example configs"
  grep -q '^texsim_prefix="/usr"$' "$root/usr/share/texsim/jobs/slurm/texsim.sbatch" ||
    fail "the packaged Slurm template does not run /usr/bin/texsim"
  [[ $("$root/usr/bin/texsim" --version) == *"prefix: $root/usr"* ]] ||
    fail "the packaged texsim does not run"
}

test_lmod_module_puts_texsim_on_path() {
  install_prefix
  local init=/usr/share/lmod/lmod/init/bash
  [ -f "$init" ] || fail "Lmod is not installed ($init missing): scripts/setup-deps installs lmod"
  local found
  found=$(env -i HOME="$work" PATH=/usr/bin:/bin bash --norc -c "
    source $init >/dev/null 2>&1
    module use $prefix/share/texsim/modulefiles
    module load texsim
    echo \"\$(command -v texsim) \$TEXSIM_DATA\"") || fail "module load texsim failed"
  [ "$found" = "$prefix/bin/texsim $prefix/share/texsim/data" ] ||
    fail "after module load texsim: '$found', expected '$prefix/bin/texsim $prefix/share/texsim/data'"
}

declare -F "test_$case_name" >/dev/null || fail "no test case '$case_name'"
"test_$case_name"
echo "PASS: $case_name"

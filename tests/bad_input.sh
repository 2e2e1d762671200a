#!/usr/bin/env bash
# Bad input as a new user would give it: each run must exit non-zero, print
# an error naming the problem, and leave the output already there untouched.
# usage: bad_input.sh SOFTFLOW MPIEXEC CASE
set -u
exe=$1 mpiexec=$2 case=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out="$work/out"
mkdir -p "$out"
echo "earlier results" >"$out/series.csv"
before=$(cd "$out" && ls -l --time-style=full-iso | md5sum; cat series.csv | md5sum)
fails=0

expect_failure() {  # expect_failure "message fragment" command...
  local want=$1
  shift
  local log
  log=$("$@" 2>&1)
  local rc=$?
  if [ $rc -eq 0 ]; then
    echo "FAIL (exit 0): $*"; fails=$((fails + 1))
  elif ! grep -qF -- "$want" <<<"$log"; then
    echo "FAIL (message): $*"; echo "  wanted: $want"; echo "  got: $log"; fails=$((fails + 1))
  else
    echo "ok: $want"
  fi
}

run() { "$exe" "$@" --set "output.dir=\"$out\"" --set output.progress_every=0; }
expect_failure "cannot open case file '$work/missing.toml'" "$exe" "$work/missing.toml"
expect_failure "unknown key 'grid.nxx'" run "$case" --set grid.nxx=3
expect_failure "'fluid.mu' must be positive (got -1)" run "$case" --set fluid.mu=-1
expect_failure "'grid.lx' must be positive" run "$case" --set grid.lx=0
expect_failure "missing key 'grid.nx'" "$exe" <(grep -v '^nx' "$case") --set "output.dir=\"$out\""
expect_failure "grid.nx = 33 is not divisible by parallel.px = 2" \
  "$mpiexec" -n 2 "$exe" "$case" --set grid.nx=33 --set parallel.px=2 --set parallel.pz=1 --set "output.dir=\"$out\""
expect_failure "output folder '/proc/softflow' cannot be created" "$exe" "$case" --set 'output.dir="/proc/softflow"'
expect_failure "restart file '$work/none.h5' does not exist" run "$case" --restart "$work/none.h5"
expect_failure "unknown option '--bogus'" "$exe" "$case" --bogus
# a check made where the solid phase is set up, not in the case file's parser
expect_failure "'particles.debris_return' works on one phi field" run "$case" --set particles.radius=0.2 \
  --set particles.count=2 --set particles.shear_modulus=1.0 --set particles.debris_return=true

after=$(cd "$out" && ls -l --time-style=full-iso | md5sum; cat series.csv | md5sum)
if [ "$before" != "$after" ]; then
  echo "FAIL: the output folder changed"; ls -la "$out"; fails=$((fails + 1))
fi
echo "$((10 - fails)) of 10 bad inputs rejected cleanly"
[ $fails -eq 0 ]

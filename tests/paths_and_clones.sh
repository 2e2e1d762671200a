#!/usr/bin/env bash
# Paths anywhere and clones side by side, through scripts/run-case.sh and
# scripts/toolchain.sh on the host (so not a ctest: ctest runs inside the
# toolchain root). Run by .ci/run after scripts/test.sh:
#   tests/paths_and_clones.sh [SOFTFLOW_EXECUTABLE]     (default: build/softflow)
# 1. A case file, its output and its restart under a temporary folder outside
#    the clone, all given relative to the caller's folder: the run writes
#    there, the restart continues from there.
# 2. Paths the root cannot see stop the run, naming them, before it starts.
# 3. Two clones run cases at once, overlapping in time, each writing through
#    its own /src: each output is complete and in its own clone.
# 4. toolchain.sh called from inside the root (setup and run) works.
set -uo pipefail
repo=$(cd "$(dirname "$0")/.." && pwd -P)
exe=${1:-$repo/build/softflow}
[ -x "$exe" ] || { echo "no softflow at $exe: run scripts/test.sh first"; exit 1; }
export SOFTFLOW_EXE=$exe OMP_NUM_THREADS=1
work=$(mktemp -d /tmp/softflow-paths.XXXXXX)
trap 'rm -rf "$work"' EXIT
fails=0
ok() { echo "ok: $*"; }
bad() { echo "FAIL: $*"; fails=$((fails + 1)); }
check() { if eval "$1"; then ok "$2"; else bad "$2"; fi; }
# the strain of the last row of a series.csv
last_strain() { tail -n 1 "$1" 2>/dev/null | cut -d, -f3; }
reached() { awk -v s="$(last_strain "$1")" -v e="$2" 'BEGIN { exit !(s != "" && s >= e - 1e-9) }'; }
small=(--set grid.nx=16 --set grid.ny=8 --set grid.nz=16 --set output.progress_every=0)

echo "== 1. case file, output and restart outside the clone, relative to the caller (${SECONDS} s)"
mkdir -p "$work/cases" "$work/here"
sed 's|^dir = .*|dir = "rel-out"|' "$repo/cases/couette.toml" >"$work/cases/c.toml"
cd "$work/here"
"$repo/scripts/run-case.sh" ../cases/c.toml "${small[@]}" --set time.end_strain=1 --set time.max_steps=30 \
  --set output.checkpoint_every=10 >log1 2>&1
check '[ -f rel-out/checkpoint.h5 ] && [ -f rel-out/series.csv ]' \
  "output.dir of the case file, relative: written under the caller's folder ($work/here/rel-out)"
check '[ ! -e "$repo/rel-out" ] && [ ! -e "$work/cases/rel-out" ]' "nothing in the clone or next to the case file"
"$repo/scripts/run-case.sh" ../cases/c.toml "${small[@]}" --set time.end_strain=1 --restart rel-out/checkpoint.h5 \
  >log2 2>&1
check 'grep -q "restarted from rel-out/checkpoint.h5 at step 30" log2 && reached rel-out/series.csv 1' \
  "--restart relative to the caller: continued from step 30 to strain 1"
check '[ -f rel-out/summary.json ] && [ -f rel-out/fields.xdmf ]' "summary and snapshots in place"
"$repo/scripts/run-case.sh" "$work/cases/c.toml" "${small[@]}" --set time.end_strain=0.2 \
  --set "output.dir=\"$work/abs-out\"" >log3 2>&1
check 'reached "$work/abs-out/series.csv" 0.2' "absolute case file and --set output.dir under /tmp"

echo "== 2. paths the toolchain root cannot see (${SECONDS} s)"
root=${SOFTFLOW_ROOT:-/var/cache/softflow/trixie-v1}
hidden=/var/tmp/softflow-paths-test-$$
"$repo/scripts/run-case.sh" ../cases/c.toml "${small[@]}" --set "output.dir=\"$hidden\"" >log4 2>&1
rc=$?
check '[ $rc = 2 ] && grep -q "softflow: error: output folder .$hidden." log4 && [ ! -e "$root$hidden" ] && [ ! -e "$hidden" ]' \
  "output.dir under /var: exit 2, named, nothing created inside the root"
"$repo/scripts/run-case.sh" ../cases/c.toml "${small[@]}" --restart /usr/share/none.h5 >log5 2>&1
rc=$?
check '[ $rc = 2 ] && grep -q "restart file ./usr/share/none.h5." log5' "--restart under /usr: exit 2, named"
(cd /usr && "$repo/scripts/run-case.sh" "$work/cases/c.toml") >log6 2>&1
rc=$?
check '[ $rc = 2 ] && grep -q "current folder ./usr." log6' "called from /usr: exit 2, the folder named"
if command -v python3 >/dev/null; then
  python3 "$repo/scripts/run-set.py" --cases phi0016_ca2 --out "$hidden" >log7 2>&1
  rc=$?
  check '[ $rc = 2 ] && grep -q "$hidden" log7 && [ ! -e "$hidden" ]' "run-set.py --out under /var: exit 2, named, before any run"
fi

echo "== 3. two clones at once (${SECONDS} s)"
# the clones get this working tree's scripts (committed or not: the ones under test)
for c in a b; do
  git clone -q "$repo" "$work/clone-$c" && cp -r "$repo/scripts/." "$work/clone-$c/scripts/" &&
    echo "$c" >"$work/clone-$c/marker"
done
mkdir -p "$work/elsewhere"
# clone a writes through /src (its own repository inside the root), from its own folder
(cd "$work/clone-a" && scripts/run-case.sh cases/couette.toml --set output.progress_every=200 \
  --set time.end_strain=6 --set 'output.dir="/src/out"' >"$work/run-a.log" 2>&1; echo $? >"$work/rc-a") &
pid_a=$!
for _ in $(seq 600); do [ -f "$work/clone-a/out/series.csv" ] && break; sleep 0.1; done
# clone b starts while a runs, from a folder outside both clones, also through /src
(cd "$work/elsewhere" && "$work/clone-b/scripts/run-case.sh" ../clone-b/cases/couette.toml \
  --set output.progress_every=200 --set time.end_strain=3 --set 'output.dir="/src/out"' \
  >"$work/run-b.log" 2>&1; echo $? >"$work/rc-b") &
pid_b=$!
sleep 1
a_running_when_b_started=no
kill -0 $pid_a 2>/dev/null && [ ! -f "$work/rc-a" ] && a_running_when_b_started=yes
seen=$("$work/clone-b/scripts/toolchain.sh" run cat /src/marker 2>/dev/null)
seen_a=$(cd "$work/clone-a" && scripts/toolchain.sh run cat /src/marker 2>/dev/null)
wait $pid_a $pid_b
check '[ $a_running_when_b_started = yes ]' "the runs overlapped (a still running when b started)"
check '[ "$seen" = b ] && [ "$seen_a" = a ]' "each invocation sees its own clone at /src"
for c in a b; do
  end=$([ $c = a ] && echo 6 || echo 3)
  d=$work/clone-$c/out
  check '[ "$(cat "$work/rc-$c")" = 0 ] && grep -q "^done:" "$work/run-$c.log"' "clone $c: run finished (exit 0)"
  check 'reached "$d/series.csv" $end && [ -f "$d/summary.json" ] && [ -f "$d/checkpoint.h5" ] && [ $(ls "$d"/fields_*.h5 | wc -l) = $((end + 1)) ] && ! ls "$d"/*.tmp >/dev/null 2>&1' \
    "clone $c: output complete in its own clone (series to strain $end, $((end + 1)) snapshots, checkpoint, summary, no .tmp)"
done
check '[ ! -e "$work/elsewhere/out" ] && [ ! -e "$repo/out" ]' "nothing written elsewhere"

echo "== 4. the toolchain called again from inside its root (${SECONDS} s)"
# a script run with the root's python (scripts/run-set.py does) calls
# toolchain.sh setup and run again: setup is a no-op there, run runs as is
nested=$(cd "$repo" && scripts/toolchain.sh run bash -c 'scripts/toolchain.sh setup && scripts/toolchain.sh run echo inside' 2>&1)
check '[ "$(echo "$nested" | tail -n 1)" = inside ]' "toolchain.sh setup and run from inside the root"

echo "$fails failure(s)"
[ $fails = 0 ]

#!/usr/bin/env bash
# vaw-sim run's output files are complete or untouched: a run cut short by a file-size limit fails
# with the file named and leaves the previous run's files; concurrent runs into one directory leave the
# three files of one run (its session replays to exactly its trajectories).
#   output_integrity.sh VAW_SIM SOURCE_DIR WORK_DIR
set -eu
sim=$1 src=$2 work=$3
rm -rf "$work" && mkdir -p "$work"
sleeve=(sleeve-on-shaft.vaw.json --inputs "$src/tests/sim/scripts/sleeve-turnover.vaw-inputs.json")
hoist=(hoist-demo.vaw.json --inputs "$src/tests/sim/scripts/hoist-demo.vaw-inputs.json")

# 1. A good run, then one that hits a 32 KiB file-size limit while streaming trajectories.csv.
"$sim" run "${sleeve[@]}" --out "$work/out" >/dev/null
cp -r "$work/out" "$work/good"
set +e
err=$( (ulimit -f 32; "$sim" run "${sleeve[@]}" --out "$work/out") 2>&1 >/dev/null)
status=$?
set -e
echo "$err"
[ "$status" -eq 1 ] || { echo "FAIL: exit status $status under the file-size limit, expected 1"; exit 1; }
echo "$err" | grep -q "cannot write .*trajectories.csv: File too large" || { echo "FAIL: the message must name trajectories.csv"; exit 1; }
for f in trajectories.csv transitions.csv session.vaw-session.json; do
  cmp -s "$work/good/$f" "$work/out/$f" || { echo "FAIL: $f changed by the failed run"; exit 1; }
done
leftovers=$(find "$work/out" -name '*.tmp' | wc -l)
[ "$leftovers" -eq 0 ] || { echo "FAIL: $leftovers temporary files left behind"; exit 1; }

# 2. Four concurrent runs of two different scenes into one directory.
pids=()
for i in 1 2 3 4; do
  if [ $((i % 2)) -eq 0 ]; then args=("${sleeve[@]}"); else args=("${hoist[@]}"); fi
  "$sim" run "${args[@]}" --out "$work/shared" >/dev/null & pids+=($!)
done
for p in "${pids[@]}"; do wait "$p" || { echo "FAIL: a concurrent run failed"; exit 1; }; done
"$sim" run --replay "$work/shared/session.vaw-session.json" --out "$work/replayed" >/dev/null
for f in trajectories.csv transitions.csv; do
  cmp -s "$work/shared/$f" "$work/replayed/$f" || { echo "FAIL: $f is not from the run that wrote the session"; exit 1; }
done
echo "output integrity OK"

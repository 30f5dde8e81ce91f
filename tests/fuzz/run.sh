#!/usr/bin/env bash
# Runs every fuzzer for SECONDS each (default 15: the bounded run of .ci/run), seeded from the bundled
# scenes, property files, input scripts, a recorded session, the bundled STL meshes, the bundled STEP
# sample (the reader's first pass) and the results the STEP reader writes for it and for a bad file (the
# plugin's result parser; those two only when the build has the STEP plugin). New inputs are
# kept in BUILD/fuzz-corpus/NAME between runs; a finding stops the run with the fuzzer's report and the
# input that caused it (BUILD/fuzz-corpus/NAME/crash-*).
# BUILD is the sanitizer build that holds the harnesses (cmake --preset asan; default build-asan).
#   tests/fuzz/run.sh [SECONDS [BUILD]]        e.g. tests/fuzz/run.sh 600 for a longer run
set -euo pipefail
seconds=${1:-15}
root=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${2:-$root/build-asan}" && pwd)
declare -A seeds=(
  [scene]="$root/resources/scenes"
  [properties]="$root/resources/properties"
  [inputs]="$root/tests/sim/scripts"
  [session]="$root/tests/fuzz/seeds/session"
  [mesh]="$root/resources/meshes"
  [step_first_pass]="$root/resources/step"
  [step_result]="$build/fuzz-seeds/step_result"
)
names="scene properties inputs session mesh"
if [ -x "$build/bin/fuzz_step_result" ]; then
  names="$names step_first_pass step_result"
  # Open CASCADE's own leaks are not the reader's (tests/sanitizers/lsan-opencascade.supp).
  export LSAN_OPTIONS="suppressions=$root/tests/sanitizers/lsan-opencascade.supp"
  reader=$build/lib/vaw/plugins/vaw-step-import
  mkdir -p "${seeds[step_result]}"
  "$reader" "$root/resources/step/bolted-bracket.stp" --relative-deflection 0.05 --out "${seeds[step_result]}/sample.cbor" >/dev/null
  printf 'not a STEP file\n' >"$build/fuzz-seeds/bad.stp"
  "$reader" "$build/fuzz-seeds/bad.stp" --out "${seeds[step_result]}/error.cbor" >/dev/null 2>&1 || true
fi
for name in $names; do
  corpus=$build/fuzz-corpus/$name
  mkdir -p "$corpus"
  echo "fuzz_$name: ${seconds} s"
  seed=${seeds[$name]}
  if [ "$name" = mesh ]; then  # libFuzzer takes folders; the mesh fuzzer reads only the binary STL files
    seed=$build/fuzz-seeds/mesh
    mkdir -p "$seed" && cp "${seeds[$name]}"/*.stl "$seed"/
  fi
  (cd "$corpus" && "$build/bin/fuzz_$name" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 \
     -print_final_stats=1 -artifact_prefix="$corpus/" "$corpus" "$seed" 2>&1 | tail -n 12)
done
echo "fuzzing: no findings"

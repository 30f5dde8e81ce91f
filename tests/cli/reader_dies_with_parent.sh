#!/usr/bin/env bash
# The STEP reader ends when whoever started it is killed (SIGKILL, as a time limit or a crash ends it):
# with VAW_STEP_READER_FAULT=hang the reader would otherwise run for ever with parent 1.
#   reader_dies_with_parent.sh VAW_SIM FILE.stp
# Uses /proc only (no procps), so it runs on a bare Debian.
set -u
"$1" inspect "$2" >/dev/null 2>&1 &
parent=$!
childOf() {
  for s in /proc/[0-9]*/status; do
    if grep -q "^PPid:[[:space:]]*$1\$" "$s" 2>/dev/null && grep -q "^Name:[[:space:]]*vaw-step-impor" "$s" 2>/dev/null; then
      basename "$(dirname "$s")"
      return
    fi
  done
}
# Ended: gone, or a zombie waiting for whoever adopted it.
ended() { [ ! -e "/proc/$1/status" ] || grep -q "^State:[[:space:]]*Z" "/proc/$1/status" 2>/dev/null; }
reader=""
for _ in $(seq 1 200); do
  reader=$(childOf "$parent")
  [ -n "$reader" ] && break
  sleep 0.05
done
if [ -z "$reader" ]; then echo "FAIL: no reader started under $parent"; kill -9 "$parent" 2>/dev/null; exit 1; fi
kill -9 "$parent"
start=$(date +%s%N)
for _ in $(seq 1 100); do
  if ended "$reader"; then
    elapsed=$(( ($(date +%s%N) - start) / 1000000 ))
    printf 'OK: the reader ended %d.%03d s after its parent was killed\n' $((elapsed / 1000)) $((elapsed % 1000))
    exit 0
  fi
  sleep 0.01
done
echo "FAIL: reader $reader still running 1 s after its parent was killed"
kill -9 "$reader" 2>/dev/null
exit 1

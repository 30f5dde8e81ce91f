#!/usr/bin/env bash
# Runs a command that must fail cleanly: the given exit status (never a signal or an abort) and a
# message on stderr matching a regular expression.
#   check_error.sh STATUS REGEX -- COMMAND [ARGS...]
set -u
want=$1 pattern=$2
shift 3
err=$("$@" 2>&1 >/dev/null)
got=$?
printf '%s\n' "$err"
if [ "$got" -ne "$want" ]; then echo "FAIL: exit status $got, expected $want"; exit 1; fi
if ! printf '%s' "$err" | grep -Eq -- "$pattern"; then echo "FAIL: no message matching: $pattern"; exit 1; fi
echo "OK"

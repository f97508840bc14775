#!/usr/bin/env bash
# Runs a command and checks its exit code and that its output (stdout + stderr) matches a regex:
#   expect_cli.sh <expected exit code> <extended regex> <command> [args...]
# Used by ctest for the command-line programs, whose exit codes and messages are their interface.
set -u
expected_exit=$1
pattern=$2
shift 2
output=$("$@" 2>&1)
actual_exit=$?
printf '%s\n' "$output"
if [ "$actual_exit" -ne "$expected_exit" ]; then
  echo "expect_cli: exit code $actual_exit, expected $expected_exit" >&2
  exit 1
fi
if ! printf '%s\n' "$output" | grep -Eq -- "$pattern"; then
  echo "expect_cli: output does not match /$pattern/" >&2
  exit 1
fi

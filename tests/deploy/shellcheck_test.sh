#!/usr/bin/env bash
# tests/deploy/shellcheck_test.sh SOURCE_DIR: shellcheck, at its default severity (style
# included), on every shell script of deploy/ (*.sh and the Slurm batch scripts) and of this
# directory. A script that needs an exception says so next to the line, with the reason.
set -euo pipefail
cd "$1"
command -v shellcheck >/dev/null || {
  echo "FAIL: shellcheck not found (deploy/install-deps.sh installs it)"
  exit 1
}
mapfile -t scripts < <(find deploy tests/deploy -type f \( -name '*.sh' -o -name '*.sbatch' \) |
  sort)
[ "${#scripts[@]}" -gt 0 ] || { echo "FAIL: no scripts found"; exit 1; }
# Batch scripts are bash (#!/bin/bash) whatever their extension says.
shellcheck --shell=bash --external-sources "${scripts[@]}"
version="$(shellcheck --version | sed -n 's/^version: //p')"
echo "PASS: shellcheck $version on ${#scripts[@]} scripts:"
printf '  %s\n' "${scripts[@]}"

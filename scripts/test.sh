#!/usr/bin/env bash
# Setup command 2: install, build everything, run all tests (slow ones too), a benchmark smoke run
# and one minute of each fuzz target.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release
bash bench/run_smoke.sh
# Fuzzing (clang, libFuzzer + ASan + UBSan): each target one minute from its seed corpus, with a
# fixed seed so that what CI finds can be found again (long hunts: scripts/fuzz.sh, random seeds).
for target in ogr_wkb snap config; do
  bash scripts/fuzz.sh "$target" 60 -seed=1
done

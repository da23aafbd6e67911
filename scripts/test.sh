#!/usr/bin/env bash
# Setup command 2: install, build everything, run all tests (slow ones too) and a benchmark smoke run.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset release
cmake --build --preset release
ctest --preset release
bash bench/run_smoke.sh

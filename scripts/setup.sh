#!/usr/bin/env bash
# Setup command 1: install, build the tool, and run the main job on the bundled sample.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install_deps.sh
cmake --preset release
cmake --build --preset release --target trisnap trisnap_docs # the docs: for cmake --install (below)
mkdir -p build/sample
./build/release/src/app/trisnap snap data/delft_partition_sample.gpkg build/sample/delft_snapped.gpkg \
  --tolerance 0.05 --overwrite --report build/sample/delft_report.json
echo "sample output: build/sample/delft_snapped.gpkg (report: build/sample/delft_report.json)"
echo "trisnap: $(pwd)/build/release/src/app/trisnap (not on PATH; 'cmake --install build/release --prefix ~/.local'" \
  "puts it in ~/.local/bin, with its man page and completion: README, Install)"

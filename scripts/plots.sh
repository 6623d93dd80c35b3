#!/usr/bin/env bash
# Regenerates the plots of docs/tools.md (docs/plots/*.svg) from the built ahdpack:
#   bench_bc6h.svg  BC6H speed against error per quality level on tests/data/bc6h, with the
#                   published peers of tests/data/bc6h/PEERS.md (src/cli/peers_bc6h.cpp)
#   profiles.svg    bytes per texel against error per profile (ahdpack report profiles)
# Usage: bash scripts/plots.sh [BUILD_DIR]   (default ./build; speeds depend on the machine's load)
set -euo pipefail
cd "$(dirname "$0")/.."
bin="${1:-build}/ahdpack"
mkdir -p docs/plots
"$bin" bench bc6h --codecs bc6h --plot docs/plots/bench_bc6h.svg
"$bin" report profiles --plot docs/plots/profiles.svg

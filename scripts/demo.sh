#!/usr/bin/env bash
# Builds dqkit and runs the main demo. Installs its Debian packages when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build/release -j "$(nproc)" --target seed_walkthrough
build/release/examples/seed_walkthrough

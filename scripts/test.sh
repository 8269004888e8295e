#!/usr/bin/env bash
# Builds and runs the whole test suite: a Release build, then the same suite under
# AddressSanitizer + UndefinedBehaviorSanitizer. Installs its Debian packages when missing.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
jobs=$(nproc)

run_suite() {  # name, extra cmake flags...
  local dir=build/$1; shift
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  ctest --test-dir "$dir" -j "$jobs" --output-on-failure --timeout 600
}

echo "== Release build and tests"
run_suite release
echo "== AddressSanitizer + UndefinedBehaviorSanitizer build and tests"
run_suite asan-ubsan -DDQKIT_SANITIZE=ON -DDQKIT_BUILD_BENCHMARKS=OFF

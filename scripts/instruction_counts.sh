#!/usr/bin/env bash
# Instructions per operation of the one-at-a-time cases whose time targets are missed
# (docs/performance.md), with their peers, counted by callgrind: this machine kind has no hardware
# counters for `perf stat`. bench/instruction_counts runs 1024 operations per round; each case
# runs for 20 and for 40 rounds, and the difference, divided by 20 × 1024, cancels start-up and
# set-up. Both builds: portable (build/release) and -mavx2 -mfma (build/bench-avx2, configured as
# scripts/performance.py does).
#   scripts/instruction_counts.sh        (needs valgrind: apt-get install valgrind)
set -euo pipefail
cd "$(dirname "$0")/.."
command -v valgrind > /dev/null || { echo "instruction_counts.sh: valgrind is not installed" >&2; exit 1; }

cmake -S . -B build/release -DCMAKE_BUILD_TYPE=Release > /dev/null
cmake --build build/release -j "$(nproc)" --target instruction_counts > /dev/null
cmake -S . -B build/bench-avx2 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-mavx2 -mfma" -DDQKIT_BUILD_TESTS=OFF \
  -DDQKIT_BUILD_PYTHON=OFF -DDQKIT_BUILD_DEMOS=OFF -DDQKIT_BUILD_TOOLS=OFF -DDQKIT_BUILD_EXAMPLES=OFF > /dev/null
cmake --build build/bench-avx2 -j "$(nproc)" --target instruction_counts > /dev/null

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
# Instructions of one run of `program case rounds`.
instructions() {
  valgrind --tool=callgrind --callgrind-out-file="$out/cg" "$1" "$2" "$3" > /dev/null 2> "$out/log"
  awk '/^(summary|totals):/ { print $2; exit }' "$out/cg"
}
echo "| case | instructions per operation, portable | with -mavx2 -mfma |"
echo "| --- | ---: | ---: |"
for c in chain_dqkit chain_eigen_matrix4f chain_eigen_matrix4f_two_buffers compose_dqkit compose_glm_dualquat point_dqkit point_eigen_isometry3f point_glm_mat4 point_glm_dualquat \
         slerp_dqkit slerp_eigen slerp_glm; do
  row="| $c"
  for build in build/release build/bench-avx2; do
    p="$build/bench/instruction_counts"
    n1=$(instructions "$p" "$c" 20)
    n2=$(instructions "$p" "$c" 40)
    row="$row | $(awk -v a="$n1" -v b="$n2" 'BEGIN { printf "%.1f", (b - a) / (20 * 1024) }')"
  done
  echo "$row |"
done

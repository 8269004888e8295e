#!/usr/bin/env bash
# Builds the libFuzzer targets with clang and runs each for a bounded time (default 60 s), two at
# a time. Seeds: the committed corpus plus, for the importers, the sample files of Debian's
# assimp-testmodels. A crash stops the run with the input saved under <build>/artifacts/ (build/fuzz
# unless DQKIT_FUZZ_BUILD names another); copy it to fuzz/regressions/<target>/ so that CTest
# replays it from then on.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-60}
# DQKIT_FUZZ_BUILD: a build folder (relative to the repository's root) already configured with
# -DDQKIT_FUZZ=ON and the tools (scripts/test.sh passes its sanitizer build, which compiles the
# libraries once for its tests and these targets); without it, build/fuzz is configured here.
build=${DQKIT_FUZZ_BUILD:-build/fuzz}
if [ -n "${DQKIT_FUZZ_BUILD:-}" ]; then
  grep -Eiq '^DQKIT_FUZZ:BOOL=(ON|1|TRUE|YES|Y)$' "$build/CMakeCache.txt" || { echo "$build is not configured with -DDQKIT_FUZZ=ON"; exit 1; }
else
  scripts/deps.sh
  # -O1 with line tables only: stack traces with file and line, lighter to build than full debug
  # information.
  CC=clang CXX=clang++ cmake -S . -B "$build" -DCMAKE_BUILD_TYPE=RelWithDebInfo "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O1 -gline-tables-only -DNDEBUG" -DDQKIT_FUZZ=ON \
    -DDQKIT_BUILD_TESTS=OFF -DDQKIT_BUILD_BENCHMARKS=OFF -DDQKIT_BUILD_EXAMPLES=OFF >/dev/null
fi
targets=$(cmake --build "$build" --target help | sed -n 's/^\.\.\. \(fuzz_[a-z_]*\).*/\1/p' | sort -u)
cmake --build "$build" -j "$(nproc)" --target $targets dqkit_cli
rm -rf "$build/artifacts" && mkdir -p "$build/artifacts" "$build/work"
models=/usr/share/assimp/models

run_one() {
  local target=$1 seconds=$2 build=$3 models=$4
  local name=${target#fuzz_}
  local corpus=${name#import_}
  local work="$build/work/$name"
  rm -rf "$work" && mkdir -p "$work"
  cp fuzz/corpus/"$corpus"/* "$work"/ 2>/dev/null || true
  if [[ $name == import_* ]]; then  # package-provided sample files as extra seeds (small ones)
    find "$models" -iname "*.$corpus" -size -300k 2>/dev/null | head -20 | while read -r f; do cp "$f" "$work/"; done
  fi
  # Assimp 5.2 (a system library, not dqkit) crashes, hangs, leaks and over-allocates on some
  # malformed files. The importer targets therefore run in libFuzzer's fork mode, which goes on
  # after such a crash; afterwards every crashing input must (a) not crash inside dqkit's own code
  # and (b) give a clean error through dqkit's isolated importer (the CLI), never a crash.
  # Memory limits: dqkit's own targets must stay within 1 GB resident and 256 MB per allocation
  # (a declared count trusted for allocation, or output built in memory, is found as an
  # out-of-memory crash).
  local extra=(-rss_limit_mb=1024 -malloc_limit_mb=256)
  [[ $name == import_* ]] && extra=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 -rss_limit_mb=4096 -detect_leaks=0)
  # (Fork mode exits non-zero after ignored crashes: for the importers the checks below decide.)
  # A fixed seed makes a CI run reproducible: the same inputs are tried, in the same order.
  if ! "$build/fuzz/$target" -seed=1 -max_total_time="$seconds" -timeout=10 "${extra[@]}" -print_final_stats=1 \
      -artifact_prefix="$build/artifacts/$name-" "$work" > "$build/$name.log" 2>&1 && [[ $name != import_* ]]; then
    echo "$name: CRASH (see $build/$name.log and $build/artifacts/)"
    tail -30 "$build/$name.log"
    return 1
  fi
  local runs
  if [[ $name == import_* ]]; then  # fork mode reports progress lines "#N: cov: ..."
    runs=$(grep -o '^#[0-9]*: cov' "$build/$name.log" | tail -1 | tr -dc '0-9')
  else
    runs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$build/$name.log" | grep -o '[0-9]*$' | tail -1)
  fi
  if [[ $name == import_* ]]; then
    if grep -A8 'ERROR: AddressSanitizer\|runtime error\|deadly signal' "$build/$name.log" | grep -Eq '^ *#[0-9]+ 0x[0-9a-f]+ in dq::'; then
      echo "$name: CRASH in dqkit code (see $build/$name.log)"
      return 1
    fi
    local crashes=0
    for a in "$build/artifacts/$name"-*; do
      [ -e "$a" ] || continue
      crashes=$((crashes + 1))
      cp "$a" "$build/work/replay.$corpus"
      # The tool is built with the sanitizers, whose reports exit with 1 unless told otherwise:
      # told 86 here, so that a finding cannot pass for a clean error.
      ASAN_OPTIONS=exitcode=86 UBSAN_OPTIONS=exitcode=86 \
        "$build/tools/dqkit" info --import-timeout 5 "$build/work/replay.$corpus" > /dev/null 2>&1
      local code=$?
      # 1: a clean error; 0: the file imports after all (an out-of-memory input that fits in the
      # isolated importer's larger limit). Anything else would be a crash of the tool.
      if [ "$code" -ne 1 ] && [ "$code" -ne 0 ]; then
        echo "$name: the isolated importer did not turn $a into a clean error or a result (exit $code)"
        return 1
      fi
    done
    echo "$name: $runs runs in ${seconds}s; $crashes Assimp crash/hang/out-of-memory inputs, none of which crashes dqkit's isolated importer"
  else
    echo "$name: $runs runs in ${seconds}s, no crash"
  fi
  echo "$name $seconds $runs" >> "$build/fuzz-time.log"
}
export -f run_one
echo "== fuzzing each target for ${seconds}s"
printf '%s\n' $targets | xargs -P 2 -I{} bash -c "run_one {} $seconds $build $models"

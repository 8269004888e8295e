#!/usr/bin/env bash
# Builds and runs the whole test suite: a Release build (GCC); the same suite built with clang under
# AddressSanitizer + UndefinedBehaviorSanitizer; the tests of the numerical code built with -mavx2 -mfma (where the
# CPU has them: the results must not depend on the instruction set, docs/design.md); the threaded tests under
# ThreadSanitizer; then every fuzz target for a bounded time (DQKIT_FUZZ_SECONDS, default 8).
# Installs its Debian packages when missing. Every build, including the ones nested in tests (the
# packaging tests, pip), compiles through ccache: the same source with the same flags is compiled
# once per run (CMake reads the launcher from the environment at each build's first configure).
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/deps.sh
jobs=$(( $(nproc) + 1 ))  # one more than the cores: links and I/O overlap compiles
# (No CCACHE_BASEDIR: paths made relative to build directories of different depths would differ.)
export CMAKE_CXX_COMPILER_LAUNCHER=ccache CMAKE_C_COMPILER_LAUNCHER=ccache
stage_start=$SECONDS
stage() {  # title: closes the previous stage with its time
  echo "   (took $((SECONDS - stage_start)) s)"
  stage_start=$SECONDS
  echo "== $1"
}

summary=$(mktemp)
trap 'rm -f "$summary"' EXIT
run_ctest() {  # ctest arguments...; keeps the counts for the closing line
  ctest "$@" --output-on-failure --timeout 600 | tee -a "$summary"
}
run_suite() {  # name, ctest arguments (quoted), extra cmake flags...
  local dir=build/$1 ctest_args=$2; shift 2
  cmake -S . -B "$dir" -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_COMPILER_LAUNCHER=ccache "$@" >/dev/null
  cmake --build "$dir" -j "$jobs"
  # shellcheck disable=SC2086
  run_ctest --test-dir "$dir" -j "$jobs" $ctest_args
}

echo "== Release build and tests"
run_suite release "" -DDQKIT_TEST_OPTIMIZATION=-O2  # the test files at -O2 (tests/CMakeLists.txt says why)
stage "The renderer's window (GLFW) on a virtual X display (Xvfb); CTest ran the headless renderer"
xvfb-run -a build/release/tests/test_render --gtest_filter='Render.Window*'
stage "Python: pytest on the module of the Release build (tests/python), then pip install from pyproject.toml"
python=/usr/bin/python3  # Debian's, with NumPy (the first python3 on a PATH may be another)
if [ -d build/release/python/dqkit ]; then
  rc=0
  DQKIT_PYTHON_BUILD_DIR=build/release PYTHONPATH=build/release/python \
    "$python" -m pytest -p no:cacheprovider -q tests/python || rc=$?
  if [ "$rc" -eq 5 ]; then echo "pytest collected no tests: failing"; exit 1; fi
  [ "$rc" -eq 0 ] || exit "$rc"
  pip_target=$(mktemp -d)
  if ! "$python" -m pip install --no-build-isolation --no-deps --target "$pip_target" . >"$pip_target.log" 2>&1; then
    cat "$pip_target.log"; exit 1
  fi
  # Imported from there, with its own import worker (a glTF sample when assimp-testmodels has it).
  (cd "$pip_target" && env -u DQKIT_IMPORT_WORKER PYTHONPATH="$pip_target" "$python" -c "if True:
    import dqkit, os, sys
    assert dqkit.__file__.startswith(sys.argv[1]) and os.environ['DQKIT_IMPORT_WORKER'].startswith(sys.argv[1])
    model = '/usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf'
    joints = len(dqkit.import_scene(model).skeleton) if dqkit.HAVE_IMPORT and os.path.exists(model) else 0
    print('pip --target install imports from', sys.argv[1], '(and imported a glTF with', joints, 'joints)')" "$pip_target")
  rm -rf "$pip_target" "$pip_target.log"
else
  echo "The Release build has no Python module (DQKIT_BUILD_PYTHON off: pybind11-dev or python3-numpy missing): failing"
  exit 1
fi

stage "AddressSanitizer + UndefinedBehaviorSanitizer build with clang (-O1): the tests of the libraries, and the"
echo "   fuzz targets, whose libFuzzer binaries share this build's libraries (the packaging tests build dqkit again"
echo "   without sanitizers and ran above, as did the demos and the command-line tool's end-to-end tests; the tool"
echo "   runs under ASan + UBSan in the fuzzing stage, fuzz_cli driving its info, fk and convert commands)"
# Clang here, GCC above: every test passes with both compilers (building them with clang found
# skinning kernels whose helpers clang had left out of line), and clang instruments in half the time.
# Linked with lld: a sanitized test links in 0.4 s against 1.1 s with GNU ld, some 55 times.
run_suite asan-ubsan "-LE package" -DCMAKE_CXX_COMPILER=clang++ -DDQKIT_SANITIZE=ON -DDQKIT_FUZZ=ON -DDQKIT_BUILD_TOOLS=ON \
  "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -gline-tables-only -DNDEBUG" -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld \
  -DDQKIT_BUILD_BENCHMARKS=OFF -DDQKIT_BUILD_PYTHON=OFF -DDQKIT_BUILD_DEMOS=OFF

if grep -qw avx2 /proc/cpuinfo && grep -qw fma /proc/cpuinfo; then
  stage "Release build with -mavx2 -mfma: the tests of the algebra (dual numbers, quaternions, dual quaternions),"
  echo "   interpolation and the SIMD kernels (the code with float lane paths, whose results could depend on the"
  echo "   instruction set; the rest, test_generic's scalar-generic derivatives among it, ran above)"
  numeric_tests=(test_dual test_algebra test_interp test_simd test_pose_blocks test_skin)
  cmake -S . -B build/avx2 -DCMAKE_BUILD_TYPE=Release -DCMAKE_CXX_FLAGS="-mavx2 -mfma" -DDQKIT_BUILD_BENCHMARKS=OFF -DDQKIT_BUILD_PYTHON=OFF \
    -DDQKIT_BUILD_EXAMPLES=OFF -DDQKIT_BUILD_TOOLS=OFF -DDQKIT_WITH_ASSIMP=OFF -DDQKIT_BUILD_DEMOS=OFF >/dev/null
  cmake --build build/avx2 -j "$jobs" --target "${numeric_tests[@]}"
  run_ctest --test-dir build/avx2 -j "$jobs" -L "^($(IFS='|'; echo "${numeric_tests[*]}"))\$"
else
  stage "(this CPU has no AVX2 + FMA: the -mavx2 -mfma build is skipped)"
fi

stage "ThreadSanitizer build (-O1): the tests that use threads"
cmake -S . -B build/tsan -DCMAKE_BUILD_TYPE=Release "-DCMAKE_CXX_FLAGS_RELEASE=-O1 -DNDEBUG" -DDQKIT_TSAN=ON -DDQKIT_BUILD_BENCHMARKS=OFF \
  -DDQKIT_BUILD_EXAMPLES=OFF >/dev/null
cmake --build build/tsan -j "$jobs" --target test_threads test_skeleton test_skin test_pose_blocks  # Skinning.Threads*, PoseBlocks.Threads*
run_ctest --test-dir build/tsan -R "Threads|ForwardKinematics"

stage "Fuzzing: every target for ${DQKIT_FUZZ_SECONDS:-8} s (libFuzzer, clang; built in the sanitizer stage)"
DQKIT_FUZZ_BUILD=build/asan-ubsan scripts/fuzz.sh "${DQKIT_FUZZ_SECONDS:-8}"
stage "Summary"

# One closing line for the whole run: every CTest test of the four builds (all passed, or the
# script would have stopped above).
total=$(sed -n 's/.*tests failed out of \([0-9]*\).*/\1/p' "$summary" | awk '{s+=$1} END {print s+0}')
echo "all: $total passed, 0 failed, in $((SECONDS / 60)) min $((SECONDS % 60)) s"

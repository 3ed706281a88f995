#!/usr/bin/env bash
# Builds ellipsekit and runs the whole test suite with ctest.
#   scripts/test.sh              Release build in build/
#   scripts/test.sh --sanitize   -O1 -g1 + AddressSanitizer/UBSan in build-asan/
#   scripts/test.sh --tsan       RelWithDebInfo + ThreadSanitizer in build-tsan/, concurrency and stream tests only
# The output ends with ctest's summary; the exit status is ctest's. The Python suites (pytest, python/tests)
# are ctest tests too (python_*, `ctest -L python`), in the Release build only: the sanitizer builds
# do not build the Python module (an instrumented extension cannot load into a plain python3).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

sanitize=0
tsan=0
for arg in "$@"; do
  case "$arg" in
    --sanitize) sanitize=1 ;;
    --tsan) tsan=1 ;;
    -h|--help)
      sed -n '2,6p' "$0" | sed 's/^# \{0,1\}//'
      exit 0 ;;
    *) echo "test.sh: unknown argument: $arg (accepted: --sanitize, --tsan)" >&2; exit 2 ;;
  esac
done

scripts/setup.sh

if [[ $tsan -eq 1 ]]; then
  if [[ $sanitize -eq 1 ]]; then
    echo "test.sh: --sanitize and --tsan cannot be combined" >&2
    exit 2
  fi
  build_dir=build-tsan
  tsan_flags="-fsanitize=thread -fno-omit-frame-pointer"
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DELLIPSEKIT_BUILD_BENCH=OFF \
    -DCMAKE_CXX_FLAGS="$tsan_flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$tsan_flags" \
    -DCMAKE_SHARED_LINKER_FLAGS="$tsan_flags" \
    -DCMAKE_MODULE_LINKER_FLAGS="$tsan_flags" >/dev/null
  cmake --build "$build_dir" -j2 --target test_concurrency test_stream
  # Any data race fails the test that triggered it.
  export TSAN_OPTIONS="${TSAN_OPTIONS:-halt_on_error=1:second_deadlock_stack=1}"
  exec ctest --test-dir "$build_dir" --output-on-failure -j1 --no-label-summary -R '^(Backends/Concurrency|Stream)\.'
fi

if [[ $sanitize -eq 1 ]]; then
  build_dir=build-asan
  san_flags="-fsanitize=address,undefined -fno-omit-frame-pointer"
  # The benchmarks are not tests: left out of the sanitizer build to keep CI short. -O1 -g1 (line
  # tables: reports still name file and line) instead of RelWithDebInfo's -O2 -g: the build took
  # ~23 of CI's ~39 minutes (Eigen in robot/ under ASan), 879 s with these flags, tests 428 s
  # against 494 s (one run each, 2 cores).
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DELLIPSEKIT_BUILD_BENCH=OFF \
    -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g1 -DNDEBUG" \
    -DCMAKE_CXX_FLAGS="$san_flags" \
    -DCMAKE_EXE_LINKER_FLAGS="$san_flags" \
    -DCMAKE_SHARED_LINKER_FLAGS="$san_flags" \
    -DCMAKE_MODULE_LINKER_FLAGS="$san_flags" >/dev/null
  # Make any sanitizer report fail the test that triggered it.
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:abort_on_error=1}"
  export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
else
  build_dir=build
  cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
fi

cmake --build "$build_dir" -j2

exec ctest --test-dir "$build_dir" --output-on-failure -j2 --no-label-summary

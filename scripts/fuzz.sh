#!/usr/bin/env bash
# Fuzzes Detector::detect() with libFuzzer (clang, ASan + UBSan) on every available backend.
#   scripts/fuzz.sh [SECONDS]   run for SECONDS (default 60) in build-fuzz/
#   FUZZ_KEEP_GOING=1 scripts/fuzz.sh [SECONDS]   fork mode: go on after a crash, timeout or OOM
#   FUZZ_LEAKS=1 scripts/fuzz.sh [SECONDS]        leak-check too (CPU backends only)
# New interesting inputs go to build-fuzz/corpus (the committed seeds in fuzz/corpus are read, not
# written); a crash is saved as build-fuzz/artifacts/crash-*. Copy a small crash input into
# fuzz/corpus/ once fixed, so that ctest's fuzz_corpus_replay keeps it fixed.
# Needs clang and libclang-rt-14-dev (Debian).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

seconds="${1:-60}"
if ! [[ "$seconds" =~ ^[0-9]+$ ]]; then
  echo "fuzz.sh: SECONDS must be a whole number, got '$seconds'" >&2
  exit 2
fi
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi

build_dir=build-fuzz
flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g"
CC=clang CXX=clang++ cmake -S . -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DELLIPSEKIT_FUZZ=ON -DELLIPSEKIT_BUILD_TESTS=OFF -DELLIPSEKIT_BUILD_TOOLS=OFF -DELLIPSEKIT_BUILD_BENCH=OFF \
  -DCMAKE_CXX_FLAGS="$flags" \
  -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
cmake --build "$build_dir" -j2 --target fuzz_detect

mkdir -p "$build_dir/corpus" "$build_dir/artifacts"
# Leak checking is off by default: it would make every input pay for a leak scan, and the ctest
# suite under `scripts/test.sh --sanitize` checks leaks (Vulkan included). FUZZ_LEAKS=1 turns it on
# for the CPU backends only (Vulkan is then left out of the inputs).
if [[ "${FUZZ_LEAKS:-0}" == 1 ]]; then
  export ELLIPSEKIT_FUZZ_NO_VULKAN=1
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
else
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"
fi
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# -rss_limit_mb: a frame is at most 16400 px long, so more than 2 GB is a finding.
extra=()
if [[ "${FUZZ_KEEP_GOING:-0}" == 1 ]]; then
  extra=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
fi
exec "$build_dir/bin/fuzz_detect" "$build_dir/corpus" fuzz/corpus \
  -max_total_time="$seconds" -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
  -artifact_prefix="$build_dir/artifacts/" -print_final_stats=1 "${extra[@]}"

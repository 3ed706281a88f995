#!/usr/bin/env bash
# Fuzzes Detector::detect() with libFuzzer (clang, ASan + UBSan).
#   scripts/fuzz.sh [SECONDS] [--target detect|cpu|all]   run for SECONDS (default 60)
#   FUZZ_TARGET=cpu scripts/fuzz.sh [SECONDS]             the same choice by environment (the
#                                                         option wins when both are given)
# Targets:
#   detect (default)  fuzz_detect (fuzz/fuzz_detect.cc): every available backend, Vulkan included
#                     (a lavapipe frame dominates: a few inputs/s); built in build-fuzz/; corpus
#                     build-fuzz/corpus (written) and fuzz/corpus (committed seeds, read only);
#                     crashes in build-fuzz/artifacts/.
#   cpu               fuzz_detect_cpu (fuzz/fuzz_detect_cpu.cc): scalar and SIMD compared bit for
#                     bit on small raw or drawn frames (ellipses, rings, dot grids), no Vulkan,
#                     ~600 inputs/s; built in build-fuzz/cpu/ without Vulkan and without
#                     trace-cmp instrumentation (below); corpus build-fuzz/corpus_cpu (written) and
#                     fuzz/corpus_cpu (committed seeds); crashes in build-fuzz/artifacts_cpu/.
#   all               detect, then cpu, SECONDS each; the exit status is the first failure's.
#   FUZZ_KEEP_GOING=1 scripts/fuzz.sh ...   fork mode: go on after a crash, timeout or OOM
#   FUZZ_LEAKS=1 scripts/fuzz.sh ...        leak-check too (CPU backends only)
#   FUZZ_JOBS=N scripts/fuzz.sh ...         build with N parallel jobs (default 2)
# Copy a small crash input into fuzz/corpus/ (fuzz/corpus_cpu/ for the cpu target) once fixed, so
# that ctest's fuzz_corpus_replay (fuzz_cpu_corpus_replay) keeps it fixed.
# Needs clang and libclang-rt-14-dev (Debian).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

usage() { echo "usage: scripts/fuzz.sh [SECONDS] [--target detect|cpu|all]" >&2; exit 2; }
seconds=60
target="${FUZZ_TARGET:-detect}"
while [[ $# -gt 0 ]]; do
  case "$1" in
    --target) [[ $# -ge 2 ]] || usage; target="$2"; shift 2 ;;
    --target=*) target="${1#--target=}"; shift ;;
    -h|--help) usage ;;
    *)
      if ! [[ "$1" =~ ^[0-9]+$ ]]; then
        echo "fuzz.sh: SECONDS must be a whole number, got '$1'" >&2
        exit 2
      fi
      seconds="$1"; shift ;;
  esac
done
case "$target" in
  detect|cpu|all) ;;
  *) echo "fuzz.sh: --target must be detect, cpu or all, got '$target'" >&2; exit 2 ;;
esac
if ! command -v clang++ >/dev/null; then
  echo "fuzz.sh: clang++ not found (apt-get install clang libclang-rt-14-dev)" >&2
  exit 1
fi
jobs="${FUZZ_JOBS:-2}"

# Leak checking is off by default: it would make every input pay for a leak scan, and the ctest
# suite under `scripts/test.sh --sanitize` checks leaks (Vulkan included). FUZZ_LEAKS=1 turns it on
# for the CPU backends only (Vulkan is then left out of fuzz_detect's inputs).
if [[ "${FUZZ_LEAKS:-0}" == 1 ]]; then
  export ELLIPSEKIT_FUZZ_NO_VULKAN=1
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1}"
else
  export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=0}"
fi
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$PWD/fuzz/lsan.supp}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
keep_going=()
if [[ "${FUZZ_KEEP_GOING:-0}" == 1 ]]; then
  keep_going=(-fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1)
fi

# configure BUILD_DIR EXTRA_CXX_FLAGS [EXTRA_CMAKE_ARGS...]
configure() {
  local flags="-fsanitize=fuzzer-no-link,address,undefined -fno-sanitize-recover=undefined -fno-omit-frame-pointer -g $2"
  CC=clang CXX=clang++ cmake -S . -B "$1" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DELLIPSEKIT_FUZZ=ON -DELLIPSEKIT_BUILD_TESTS=OFF -DELLIPSEKIT_BUILD_TOOLS=OFF -DELLIPSEKIT_BUILD_BENCH=OFF \
    "${@:3}" -DCMAKE_CXX_FLAGS="$flags" \
    -DCMAKE_EXE_LINKER_FLAGS="-fsanitize=address,undefined" >/dev/null
}

# -rss_limit_mb: a frame is at most 16400 px long, so more than 2 GB is a finding.
fuzz_detect() {
  local build_dir=build-fuzz
  configure "$build_dir" ""
  cmake --build "$build_dir" -j"$jobs" --target fuzz_detect
  mkdir -p "$build_dir/corpus" "$build_dir/artifacts"
  "$build_dir/bin/fuzz_detect" "$build_dir/corpus" fuzz/corpus \
    -max_total_time="$seconds" -max_len=4096 -timeout=20 -rss_limit_mb=2048 \
    -artifact_prefix="$build_dir/artifacts/" -print_final_stats=1 "${keep_going[@]}"
}

# Built apart from fuzz_detect, without -fsanitize-coverage=trace-cmp: the comparison callbacks
# took 60-75 % of the time on these small frames (measured: the seeds of fuzz/corpus_cpu ran
# 2.6-3.8x faster without them), and the grouping's decisions are floating-point comparisons,
# which trace-cmp does not see anyway. The edge coverage counters (the fuzzer's guide) stay.
# Built without Vulkan (it never runs here; the build needs no shader compiler).
# Its coverage counters leave out the standard library's and Eigen's internals
# (fuzz/coverage_ignore.txt; ASan and UBSan still check them): 11.2k counters instead of 15.3k,
# CPU per input 3.6 -> 3.0 ms (same corpus and seed).
# -detect_leaks=0 (unless FUZZ_LEAKS=1): the harness keeps Detectors across inputs, and libFuzzer
# would re-run every input that creates one to look for a leak. -reload=0: one process, so nobody
# else adds to the corpus folder (rereading it every second cost 4 % of the time).
# -entropic_scale_per_exec_time=1: libFuzzer's entropic schedule gives an input energy by the
# rare features near it, then scales it by its run time against the corpus average (10x slower or
# more: a tenth; faster: up to 3x). The cost per input has a long tail (a 128x96 frame with
# hundreds of triplets takes 50-300 ms under ASan, 1000x a small one; 3 % of the inputs took half
# the time). Measured on the same corpus, two seeds: CPU per input 2.5-2.9 -> 1.0-1.2 ms. What
# runs shifts: frames of >= 64x48 px went from 63 % to 35 % of the inputs and inputs detect()
# refuses from 17 % to 34 %, but per CPU second 1.8x more big frames run (the cheaper ones more
# often, the 100-300 ms ones less) and big frames still take 82 % of the time (96 % before).
fuzz_detect_cpu() {
  local build_dir=build-fuzz/cpu out=build-fuzz
  configure "$build_dir" "-fno-sanitize-coverage=trace-cmp -fsanitize-coverage-ignorelist=$PWD/fuzz/coverage_ignore.txt" \
    -DELLIPSEKIT_WITH_VULKAN=OFF
  cmake --build "$build_dir" -j"$jobs" --target fuzz_detect_cpu
  mkdir -p "$out/corpus_cpu" "$out/artifacts_cpu"
  local leaks=(-detect_leaks=0)
  [[ "${FUZZ_LEAKS:-0}" == 1 ]] && leaks=()
  "$build_dir/bin/fuzz_detect_cpu" "$out/corpus_cpu" fuzz/corpus_cpu \
    -max_total_time="$seconds" -max_len=2048 -timeout=20 -rss_limit_mb=2048 -reload=0 "${leaks[@]}" \
    -entropic_scale_per_exec_time=1 -artifact_prefix="$out/artifacts_cpu/" -print_final_stats=1 "${keep_going[@]}"
}

case "$target" in
  detect) fuzz_detect ;;
  cpu) fuzz_detect_cpu ;;
  all)
    status=0
    fuzz_detect || status=$?
    fuzz_detect_cpu || { s=$?; [[ $status -ne 0 ]] || status=$s; }
    exit "$status"
    ;;
esac

#!/usr/bin/env bash
# Counts the instructions detect() executes (valgrind's callgrind), for comparing two builds whose
# difference is a few percent: the count is the same on every run, while time on a shared machine
# moves by 3-4 % between two runs of one binary. Instructions are not time (cache misses and
# mispredicted branches cost time and no instructions), so confirm a change in alternated timed runs
# too (docs/speed.md).
# Usage: scripts/count-instructions.sh [ELLIPSEKIT_BINARY] [REPEAT] [-- detect options...]
#   defaults: build/bin/ellipsekit, 3 repeats, over the shared datasets' photographs.
# Prints detect()'s inclusive instruction count (every call: the untimed warm-up and REPEAT timed
# ones per image) and writes the profile to out/callgrind.out (callgrind_annotate reads it).
# Needs valgrind (apt-get install valgrind; not part of scripts/setup.sh: CI does not use it).
#
# Two workarounds, both for valgrind 3.19: it cannot run AVX-512, so the SIMD kernels run their AVX2
# table (ELLIPSEKIT_HWY_TARGET=AVX2); and it stops at the rdtscp instruction in libhwy's own
# start-up (hwy::platform::TimerResolution, which ellipsekit never calls), so the run loads a copy
# of libhwy whose rdtscp (0f 01 f9) is replaced by rdtsc; nop (0f 31 90), in a temporary folder.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

binary="${1:-build/bin/ellipsekit}"
repeat="${2:-3}"
shift $(( $# < 2 ? $# : 2 ))
[[ "${1:-}" == "--" ]] && shift
command -v valgrind >/dev/null || { echo "count-instructions: valgrind is not installed (apt-get install valgrind)" >&2; exit 1; }
[[ -x "$binary" ]] || { echo "count-instructions: $binary is not an executable (build first: scripts/test.sh)" >&2; exit 1; }

hwy=$(ldd "$binary" | awk '/libhwy\.so/ && !found {print $3; found = 1}')
[[ -n "$hwy" ]] || { echo "count-instructions: $binary does not load libhwy" >&2; exit 1; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
python3 - "$hwy" "$tmp/$(basename "$hwy")" <<'PY'
import sys
data = open(sys.argv[1], 'rb').read()
open(sys.argv[2], 'wb').write(data.replace(b'\x0f\x01\xf9', b'\x0f\x31\x90'))
PY

mkdir -p out
images=(../shared/datasets/*/images/*)
LD_LIBRARY_PATH="$tmp" ELLIPSEKIT_HWY_TARGET=AVX2 valgrind --tool=callgrind --callgrind-out-file=out/callgrind.out \
  "$binary" detect --repeat "$repeat" "$@" "${images[@]}" >/dev/null 2>"$tmp/valgrind.log" ||
  { cat "$tmp/valgrind.log" >&2; exit 1; }
count=$(callgrind_annotate --inclusive=yes out/callgrind.out | awk '/ellipsekit::Detector::detect\(/ && !found {gsub(",", "", $1); print $1; found = 1}')
echo "detect() instructions over ${#images[@]} images x $((repeat + 1)) calls: $count (out/callgrind.out)"

#!/usr/bin/env bash
# run.sh of a bundle made by scripts/gpu-bundle.sh (this file is copied there as run.sh).
#
#   ./run.sh [--quick] [--conform-only] [--scenes N] [--out FILE] [--loader auto|system|bundle]
#
# Runs, with the bundle's libraries and the machine's Vulkan loader and GPU driver:
#   ellipsekit conform --backends scalar,simd,vulkan on the bundled dataset images and on N
#   generated scenes (ellipsekit scenes --seed 7), then
#   ellipsekit_bench: edge_stage/*, arc_stage/*, the end-to-end detect/(simd|vulkan)/* and (not with
#   --quick) the stream/(simd|vulkan)/scenes200/* benchmarks
# and writes every figure, with vulkaninfo --summary, nvidia-smi (if present), the device and the
# driver, into one results file (default: results/results.md in the bundle).
#   --quick          benchmarks with --benchmark_min_time=0.01, without scenes200 and streams (the
#                    test's mode)
#   --scenes N       generated scenes to conform on (default 200; 0 with --quick)
#   --conform-only   only the conformance run
#   --loader L       auto (default): the machine's libvulkan.so.1, else the bundle's loader/;
#                    system / bundle: that one only
# Environment: ELLIPSEKIT_VK_DEVICE (index or part of the name) picks the Vulkan device; by default a
# discrete GPU is preferred over an integrated one over a CPU device (lavapipe). VK_DRIVER_FILES /
# VK_ICD_FILENAMES are honoured; if neither is set and the only NVIDIA ICD is the one under
# /usr/local/nvidia (the device machine's layout), it is named in both.
# Exit status: 0 all ran and conform reported 0 differing; 1 otherwise; 2 bad usage.
set -uo pipefail

here=$(cd "$(dirname "$(readlink -f "${BASH_SOURCE[0]}")")" && pwd)
quick=0 conform_only=0 out="" loader_mode=auto scenes=""
while [[ $# -gt 0 ]]; do
  case "$1" in
    --quick) quick=1; shift ;;
    --conform-only) conform_only=1; shift ;;
    --scenes) scenes=$2; shift 2 ;;
    --scenes=*) scenes=${1#*=}; shift ;;
    --out) out=$2; shift 2 ;;
    --out=*) out=${1#*=}; shift ;;
    --loader) loader_mode=$2; shift 2 ;;
    --loader=*) loader_mode=${1#*=}; shift ;;
    -h|--help) sed -n '2,/^set -uo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) echo "run.sh: unknown argument $1" >&2; exit 2 ;;
  esac
done
case "$loader_mode" in auto|system|bundle) ;; *) echo "run.sh: --loader auto|system|bundle" >&2; exit 2 ;; esac
[[ -n "$scenes" ]] || { [[ $quick == 1 ]] && scenes=0 || scenes=200; }
[[ "$scenes" =~ ^[0-9]+$ ]] || { echo "run.sh: --scenes takes a count, got '$scenes'" >&2; exit 2; }
[[ -n "$out" ]] || out=$here/results/results.md
mkdir -p "$(dirname "$out")"
out=$(cd "$(dirname "$out")" && pwd)/$(basename "$out")
chmod +x "$here"/bin/* 2>/dev/null || true  # in case a copy dropped the modes
manifest() { sed -n "s/^$1=//p" "$here/MANIFEST" 2>/dev/null; }
say() { echo "$*" | tee -a "$out"; }

: >"$out"
say "# ellipsekit GPU bundle results"
say ""
say "- date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
say "- bundle: commit $(manifest commit), built $(manifest built_at) on $(manifest built_on)"
say "- machine: $(uname -srm); $( (. /etc/os-release && echo "$PRETTY_NAME") 2>/dev/null || echo 'os unknown')"
say "- cpu: $(sed -n 's/^model name[[:space:]]*: //p' /proc/cpuinfo 2>/dev/null | head -1), $(nproc 2>/dev/null || echo '?') threads"

# glibc: the one thing the bundle cannot bring.
have_glibc=$( (getconf GNU_LIBC_VERSION 2>/dev/null || ldd --version 2>/dev/null | head -1) | grep -o '[0-9][0-9]*\.[0-9][0-9]*' | head -1)
need_glibc=$(manifest glibc_needed)
say "- glibc: ${have_glibc:-unknown} (the bundle needs >= ${need_glibc:-?})"
if [[ -n "$have_glibc" && -n "$need_glibc" && "$(printf '%s\n%s\n' "$need_glibc" "$have_glibc" | sort -V | head -1)" != "$need_glibc" ]]; then
  say "run.sh: this machine's glibc $have_glibc is older than the $need_glibc the bundle was built against: rebuild the bundle on an older distribution"
  exit 1
fi

# The library path for the bundle's programs only (never exported: nvidia-smi and the shell's tools
# keep the machine's). compat/ is added only when the machine's own libstdc++/glvnd cannot load them.
libpath=$here/lib
probe() {
  (cd "$here/work" && LD_LIBRARY_PATH=$1 "$here/bin/ellipsekit" --help >/dev/null 2>"$here/work/.probe" &&
   LD_LIBRARY_PATH=$1 "$here/bin/ellipsekit_bench" --benchmark_list_tests --benchmark_filter='^edge_stage/simd/64x48' >/dev/null 2>>"$here/work/.probe")
}
if probe "$libpath"; then
  say "- libstdc++/glvnd: the machine's"
elif why=$(head -1 "$here/work/.probe"); probe "$libpath:$here/lib/compat"; then
  libpath=$libpath:$here/lib/compat
  say "- libstdc++/glvnd: the bundle's lib/compat (the machine's did not load the programs: $why)"
else
  say "run.sh: the programs do not start with the bundle's libraries:"
  sed 's/^/    /' "$here/work/.probe" | tee -a "$out"
  exit 1
fi

# The Vulkan loader: the machine's, else the bundle's copy.
system_loader=""
for f in $(ldconfig -p 2>/dev/null | awk '$1 == "libvulkan.so.1" {print $NF}') \
         /usr/lib/x86_64-linux-gnu/libvulkan.so.1 /usr/lib64/libvulkan.so.1 /usr/lib/libvulkan.so.1 \
         /usr/local/lib/libvulkan.so.1 /usr/local/nvidia/lib64/libvulkan.so.1; do
  if [[ -s "$f" ]]; then system_loader=$(readlink -f "$f"); break; fi
done
if [[ $loader_mode == bundle || ( $loader_mode == auto && -z "$system_loader" ) ]]; then
  [[ -s "$here/loader/libvulkan.so.1" ]] || { say "run.sh: no Vulkan loader on this machine and none in the bundle"; exit 1; }
  libpath=$libpath:$here/loader
  say "- Vulkan loader: the bundle's ($(cat "$here/loader/SOURCE" 2>/dev/null))"
elif [[ -z "$system_loader" ]]; then
  say "run.sh: --loader system, but this machine has no libvulkan.so.1"; exit 1
else
  say "- Vulkan loader: the machine's, $system_loader"
fi
# The device machine's driver lives under /usr/local/nvidia (its README: name its ICD if none is found).
if [[ -z "${VK_DRIVER_FILES:-}${VK_ICD_FILENAMES:-}" && -f /usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json ]] &&
   ! ls /usr/share/vulkan/icd.d/nvidia*.json /etc/vulkan/icd.d/nvidia*.json /usr/local/share/vulkan/icd.d/nvidia*.json >/dev/null 2>&1; then
  export VK_DRIVER_FILES=/usr/local/nvidia/share/vulkan/icd.d/nvidia_icd.json
  export VK_ICD_FILENAMES=$VK_DRIVER_FILES
fi
for d in /usr/local/nvidia/lib64 /usr/local/nvidia/lib; do [[ -d "$d" ]] && libpath=$libpath:$d; done
say "- ICD: VK_DRIVER_FILES=${VK_DRIVER_FILES:-unset} VK_ICD_FILENAMES=${VK_ICD_FILENAMES:-unset} ELLIPSEKIT_VK_DEVICE=${ELLIPSEKIT_VK_DEVICE:-unset}"
bundled() { LD_LIBRARY_PATH=$libpath "$@"; }

say ""
say "## Device"
say ""
say '```'
# The bundle's vulkaninfo (with the loader chosen above), else the machine's.
if [[ -x "$here/bin/vulkaninfo" ]]; then vi=(bundled "$here/bin/vulkaninfo"); else vi=(vulkaninfo); fi
if [[ "${vi[0]}" == bundled ]] || command -v vulkaninfo >/dev/null 2>&1; then
  echo "\$ vulkaninfo --summary  (${vi[*]: -1})" >>"$out"
  { "${vi[@]}" --summary 2>&1 || echo "(vulkaninfo failed: $?)"; } | grep -v 'XDG_RUNTIME_DIR' >>"$out"
else
  echo "(no vulkaninfo on this machine or in the bundle)" >>"$out"
fi
if command -v nvidia-smi >/dev/null 2>&1; then
  echo "\$ nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv" >>"$out"
  nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm --format=csv >>"$out" 2>&1
fi
say '```'

cd "$here/work" || exit 1
status=0
# conform_on TITLE IMAGE...: one conformance run, its summary and any differing rows in the results.
conform_on() {
  local title=$1; shift
  say ""
  say "## Conformance: ellipsekit conform --backends scalar,simd,vulkan $title"
  say ""
  bundled "$here/bin/ellipsekit" conform --backends scalar,simd,vulkan "$@" >"$here/work/conform.txt" 2>"$here/work/conform.err"
  local rc=$? summary differing
  summary=$(grep '^conform: ' "$here/work/conform.txt" | tail -1)
  say "$# images; exit status $rc; ${summary:-no summary line}"
  differing=$(awk '$1 == "conform" && NF == 5 && $5 != 0' "$here/work/conform.txt")
  [[ -n "$differing" ]] && { say "differing rows:"; say "$differing"; }
  if [[ -s "$here/work/conform.err" ]]; then say "stderr:"; sed 's/^/    /' "$here/work/conform.err" | tee -a "$out"; fi
  [[ $rc == 0 && "$summary" == *", 0 differing" ]] || status=1
  { echo ""; echo "<details><summary>every row</summary>"; echo ""; echo '```'; cat "$here/work/conform.txt"; echo '```'; echo "</details>"; } >>"$out"
}
conform_on "../shared/datasets/*/images/*" ../shared/datasets/*/images/*
if [[ $scenes -gt 0 ]]; then
  rm -rf "$here/work/scenes"
  if bundled "$here/bin/ellipsekit" scenes --out "$here/work/scenes" --count "$scenes" --seed 7 >/dev/null 2>"$here/work/scenes.err"; then
    conform_on "on $scenes generated scenes (ellipsekit scenes --count $scenes --seed 7)" "$here"/work/scenes/images/*
  else
    say "run.sh: ellipsekit scenes failed: $(head -1 "$here/work/scenes.err")"; status=1
  fi
fi

if [[ $conform_only == 0 ]]; then
  if [[ $quick == 1 ]]; then
    filter='^(edge_stage|arc_stage)/|^detect/(simd|vulkan)/(prasad|photos|scenes)/'
    bench_args=(--benchmark_min_time=0.01)
  else
    filter='^(edge_stage|arc_stage)/|^detect/(simd|vulkan)/|^stream/(simd|vulkan)/'
    bench_args=(--benchmark_min_time=0.2 --benchmark_repetitions=3 --benchmark_report_aggregates_only=true)
  fi
  say ""
  say "## Benchmarks: ellipsekit_bench --benchmark_filter='$filter' ${bench_args[*]}"
  say ""
  say "(run in the bundle's work/, so ../shared/datasets is the bundle's copy; real time per iteration;"
  say "the label of edge_stage/vulkan and arc_stage/vulkan rows is the Vulkan device that ran them)"
  say ""
  json=$(dirname "$out")/bench.json
  say '```'
  bundled "$here/bin/ellipsekit_bench" --benchmark_filter="$filter" "${bench_args[@]}" \
    --benchmark_out="$json" --benchmark_out_format=json --benchmark_color=false >>"$out" 2>&1
  bench_rc=$?
  say '```'
  say "exit status $bench_rc; JSON: $json"
  [[ $bench_rc == 0 ]] || status=1
  device=$(sed -n 's/^ *"label": "\(.*\)",\{0,1\}$/\1/p' "$json" 2>/dev/null | sort | uniq -c | sort -rn | head -1 | sed 's/^ *[0-9]* //')
  say ""
  say "Vulkan device (benchmark label): ${device:-not found}"
  say ""
  say "Ratios (real time; medians where there are repetitions; detect: summed over each set's images):"
  say ""
  # name time unit ... -> ms per name (the _median row if any), then the ratios.
  awk '/^(edge_stage|arc_stage|detect|stream)\// && $3 ~ /^(ns|us|ms|s)$/ {
         name = $1; sub(/\/real_time/, "", name); med = sub(/_median$/, "", name)
         if (name ~ /_(mean|stddev|cv)$/) next
         f = ($3 == "ns") ? 1e-6 : ($3 == "us") ? 1e-3 : ($3 == "s") ? 1e3 : 1
         if (med || !(name in ms)) ms[name] = $2 * f
       }
       # One table row: what, ms, the baseline ms, their ratio.
       function row(what, a, b) { printf "| %s | %.3f | %.3f | %.2f |\n", what, a, b, a / b }
       END {
         print "| what | ms | baseline ms | ms / baseline |"; print "|---|---|---|---|"
         n = split("64x48 640x480 1280x720 1920x1080", sz, " ")
         for (i = 1; i <= n; i++) if (("edge_stage/vulkan/" sz[i]) in ms && ("edge_stage/simd/" sz[i]) in ms)
           row("edge_stage " sz[i] " (baseline SIMD)", ms["edge_stage/vulkan/" sz[i]], ms["edge_stage/simd/" sz[i]])
         split("scene prasad", in_, " ")
         for (i = 1; i <= 2; i++) if (("arc_stage/vulkan/" in_[i]) in ms && ("arc_stage/scalar/" in_[i]) in ms)
           row("arc_stage " in_[i] " (baseline scalar)", ms["arc_stage/vulkan/" in_[i]], ms["arc_stage/scalar/" in_[i]])
         for (k in ms) if (k ~ /^detect\/vulkan\//) { s = k; sub(/^detect\/vulkan\//, "", s); set = s; sub(/\/.*/, "", set)
           if (("detect/simd/" s) in ms) { v[set] += ms[k]; c[set] += ms["detect/simd/" s]; cnt[set]++ } }
         split("simd vulkan", bk, " ")
         for (i = 1; i <= 2; i++) for (d = 2; d <= 3; d++) {
           st = "stream/" bk[i] "/scenes200/depth:" d; base = "stream/" bk[i] "/scenes200/detect"
           if ((st in ms) && (base in ms))
             row("stream " bk[i] " depth " d ", 200 frames (baseline detect() " bk[i] "; ratio < 1 is faster)", ms[st], ms[base])
         }
         for (d = 2; d <= 3; d++) {
           st = "stream/vulkan/scenes200/depth:" d; base = "stream/simd/scenes200/depth:" d
           if ((st in ms) && (base in ms)) row("stream vulkan depth " d ", 200 frames (baseline the SIMD stream)", ms[st], ms[base])
         }
         split("prasad photos scenes scenes200", sets, " ")
         for (i = 1; i <= 4; i++) if (cnt[sets[i]])
           row("detect " sets[i] ", " cnt[sets[i]] " rows (baseline SIMD)", v[sets[i]], c[sets[i]])
       }' "$out" | tee -a "$out"
fi
say ""
say "run.sh: done, exit status $status; results in $out"
exit $status

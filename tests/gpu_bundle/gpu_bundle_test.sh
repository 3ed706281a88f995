#!/usr/bin/env bash
# Run by ctest (tests/gpu_bundle/CMakeLists.txt): the bundle of scripts/gpu-bundle.sh runs, on
# lavapipe, from a folder outside the tree, with this machine's copies of every library it bundles
# hidden, so that nothing can resolve to the system's OpenCV, Highway or Google Benchmark.
#   1. scripts/gpu-bundle.sh --no-build into a fresh temporary folder; it must stay under 60 MiB
#      (the device tool carries at most 64 MiB with the working tree)
#   2. in a private mount namespace (unshare -m), an empty file is bind-mounted over the system's copy
#      of each bundled library (except the few the shell tools run.sh uses need), then
#      run.sh --quick: conform must report 0 differing, the results file must hold the Vulkan
#      edge_stage, arc_stage and detect rows, and libstdc++ must have come from lib/compat
#   3. the same with the system's Vulkan loader hidden too: run.sh --conform-only must use the
#      bundle's loader/ and still report 0 differing
#   4. LD_DEBUG=libs: every library the programs load whose name is a bundled one came from the bundle
# Where a mount namespace cannot be made (not root), steps 2-3 run without hiding and say so;
# step 4 is then the evidence (GPU_BUNDLE_TEST_NO_HIDING=1 forces that). Exit 77 (skipped) when
# lavapipe is not installed.
# usage: gpu_bundle_test.sh REPO BUILD_DIR
set -euo pipefail
repo=$1 build=$2
fail() { echo "gpu_bundle_test: FAIL: $*" >&2; exit 1; }

if ! ls /usr/share/vulkan/icd.d/lvp_icd*.json >/dev/null 2>&1; then
  echo "gpu_bundle_test: SKIP: no lavapipe ICD (mesa-vulkan-drivers) here"; exit 77
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/ellipsekit-gpu-bundle.XXXXXX")
trap 'rm -rf "$work"' EXIT
bundle=$work/bundle
bash "$repo/scripts/gpu-bundle.sh" --build-dir "$build" --no-build "$bundle" || fail "gpu-bundle.sh failed"
size_mib=$(du -sm "$bundle" | cut -f1)
echo "gpu_bundle_test: bundle is $size_mib MiB"
[[ $size_mib -lt 60 ]] || fail "the bundle is $size_mib MiB: over the 60 MiB that leaves room in the device tool's 64 MiB"

# The system files behind each bundled soname, minus what the tools run.sh and this test use need.
tool_libs=$(for t in bash sed grep awk sort head tail tee date uname nproc cat ls readlink dirname basename \
                     mkdir getconf ldconfig du cut xargs; do
              p=$(command -v "$t" 2>/dev/null) && [[ -f "$p" ]] && ldd "$p" 2>/dev/null || true
            done | awk '$2 == "=>" {print $1}' | sort -u)
hide=()
kept_visible=()
for f in "$bundle"/lib/*.so* "$bundle"/lib/compat/*.so*; do
  name=$(basename "$f")
  if grep -qxF "$name" <<<"$tool_libs"; then kept_visible+=("$name"); continue; fi
  while read -r p; do [[ -n "$p" ]] && hide+=("$(readlink -f "$p")"); done \
    < <(ldconfig -p | awk -v n="$name" '$1 == n {print $NF}')
done
mapfile -t hide < <(printf '%s\n' "${hide[@]}" | sort -u)
loader=$(readlink -f "$(ldconfig -p | awk '$1 == "libvulkan.so.1" && /x86-64/ && !f {print $NF; f = 1}')")
printf '%s\n' "${hide[@]}" | grep -q 'libopencv_core' || fail "no system OpenCV found to hide (is this the build machine?)"
echo "gpu_bundle_test: system copies of bundled libraries to hide: ${#hide[@]}; left visible for the shell tools: ${kept_visible[*]:-none}"
: >"$work/empty"

hidden_run() {  # hidden_run EXTRA_FILE_TO_HIDE run.sh-args...
  local extra=$1; shift
  unshare -m bash -c '
    empty=$1 extra=$2 bundle=$3; shift 3
    while read -r f; do mount --bind "$empty" "$f" || exit 90; done
    [[ -z "$extra" ]] || mount --bind "$empty" "$extra" || exit 90
    # Proof that the hiding holds inside: a hidden file reads as empty.
    [[ ! -s "$(ldconfig -p | awk '\''$1 == "libopencv_core.so.406" {print $NF; exit}'\'' | xargs readlink -f)" ]] || exit 91
    exec "$bundle/run.sh" "$@"' _ "$work/empty" "$extra" "$bundle" "$@" < <(printf '%s\n' "${hide[@]}")
}

rc=0
: >"$work/empty2"
if [[ -z "${GPU_BUNDLE_TEST_NO_HIDING:-}" ]] && unshare -m mount --bind "$work/empty" "$work/empty2" 2>/dev/null; then
  hidden=1
  hidden_run "" --quick --out "$work/results/results.md" || rc=$?
else
  hidden=0
  echo "gpu_bundle_test: NOTE: cannot bind-mount in a mount namespace here (not root?): running without hiding the system's libraries; step 4 (LD_DEBUG) is the evidence"
  "$bundle/run.sh" --quick --out "$work/results/results.md" || rc=$?
fi
results=$work/results/results.md
[[ -f "$results" ]] || fail "run.sh wrote no results file (exit $rc)"
[[ $rc == 0 ]] || { cat "$results"; fail "run.sh --quick exited $rc"; }
grep -qE '^conform: [1-9][0-9]* comparisons, 0 differing$' "$results" || fail "no 'conform: N comparisons, 0 differing' in $results"
for row in '^edge_stage/vulkan/640x480/' '^edge_stage/vulkan/64x48/' '^arc_stage/vulkan/prasad/' \
           '^detect/vulkan/prasad/' '^detect/simd/prasad/'; do
  grep -qE "$row" "$results" || fail "no benchmark row $row in $results"
done
grep -q '^Vulkan device (benchmark label): llvmpipe' "$results" || fail "the results do not name the lavapipe device"
grep -qE 'deviceName += llvmpipe' "$results" || fail "no vulkaninfo --summary naming llvmpipe in $results"
if [[ $hidden == 1 ]]; then
  grep -q '^- libstdc++/glvnd: the bundle' "$results" || fail "libstdc++ was hidden but lib/compat was not used"
  hidden_run "$loader" --conform-only --out "$work/results/loader.md" || { cat "$work/results/loader.md"; fail "run.sh --conform-only with the system loader hidden failed"; }
  grep -q "^- Vulkan loader: the bundle's" "$work/results/loader.md" || fail "the system loader was hidden but loader/ was not used"
  grep -qE 'deviceName += llvmpipe' "$work/results/loader.md" || fail "the bundle's vulkaninfo did not run with the bundle's loader"
  grep -qE '^conform: [1-9][0-9]* comparisons, 0 differing$' "$work/results/loader.md" || fail "conform with the bundle's loader differs"
fi

# Every library the programs load under a bundled name comes from the bundle (ld.so's own record).
image=$(ls "$bundle"/shared/datasets/prasad_subset/images/* | head -1)
(cd "$bundle/work" && LD_DEBUG=libs LD_LIBRARY_PATH="$bundle/lib:$bundle/lib/compat" \
   "$bundle/bin/ellipsekit" conform --backends scalar,simd,vulkan "$image" >/dev/null 2>"$work/ld_debug.txt") ||
  fail "conform under LD_DEBUG failed"
(cd "$bundle/work" && LD_DEBUG=libs LD_LIBRARY_PATH="$bundle/lib:$bundle/lib/compat" \
   "$bundle/bin/ellipsekit_bench" --benchmark_filter='^edge_stage/vulkan/64x48' --benchmark_min_time=0.01 >/dev/null 2>>"$work/ld_debug.txt") ||
  fail "ellipsekit_bench under LD_DEBUG failed"
sed -n 's/.*calling init: //p' "$work/ld_debug.txt" | sort -u >"$work/loaded.txt"
outside=$(while read -r p; do
            n=$(basename "$p")
            if [[ -e "$bundle/lib/$n" || -e "$bundle/lib/compat/$n" ]] && [[ "$p" != "$bundle"/* ]]; then echo "$p"; fi
          done <"$work/loaded.txt")
[[ -z "$outside" ]] || fail "bundled libraries loaded from outside the bundle: $outside"
grep -q "^$bundle/lib/libopencv_core" "$work/loaded.txt" || fail "libopencv_core was not loaded from the bundle"
grep -q "^$bundle/lib/libhwy" "$work/loaded.txt" || fail "libhwy was not loaded from the bundle"
grep -q "^$bundle/lib/libbenchmark" "$work/loaded.txt" || fail "libbenchmark was not loaded from the bundle"
echo "gpu_bundle_test: PASS ($(grep -c . "$work/loaded.txt") objects loaded, every bundled name from the bundle;" \
     "hidden system libraries: $([[ $hidden == 1 ]] && echo "${#hide[@]}" || echo 'none: no mount namespace'))"
grep -E '^conform: |^Vulkan device' "$results"

#!/usr/bin/env bash
# scripts/gpu-bundle.sh [options] DIR
#
# Makes DIR a self-contained bundle that runs the Vulkan checks and benchmarks on another x86-64
# Linux machine (one with a GPU driver, maybe a Vulkan loader, and none of this project's packages):
#   DIR/run.sh                 the entry point (DIR/run.sh --help)
#   DIR/bin/                   ellipsekit, ellipsekit_bench, and vulkaninfo if this machine has one
#   DIR/lib/                   every shared library they load (ldd), except the pieces below
#   DIR/lib/compat/            libstdc++, libgcc_s and glvnd's libGLX/libGLdispatch: used only when
#                              the machine's own copies do not load the programs (the machine's
#                              newer libstdc++ wins; glvnd belongs with its GPU driver)
#   DIR/loader/                this machine's Vulkan loader (libvulkan.so.1), used only when the
#                              target has none (the device machine's README says it may not)
#   DIR/shared/datasets/*/images   the shared dataset images (about 4 MB)
#   DIR/work/                  run.sh's working directory: the benchmarks read ../shared/datasets
# Never copied: the core glibc pieces (libc, libm, ld-linux, libpthread, libdl, librt and the rest of
# glibc: they use GLIBC_PRIVATE symbols of the libc they came with, so they only work as a set and
# belong to the machine), the Vulkan loader into lib/, and the GPU driver (its ICD).
#
# Options:
#   --build-dir B   take the programs from B/bin (default: build); B is configured (Release) and the two
#                   programs built in it first unless --no-build
#   --no-build      use B/bin as it is (fails if a program is missing)
#   --datasets D    the shared datasets folder (default: ../shared/datasets beside the repository)
#   --full          no trimming: every library ldd lists, as it is (about 270 MB here)
# By default the bundle is trimmed to fit the device tool's 64 MiB working-tree limit: the libraries
# that only OpenCV's optional codecs and video I/O reach (GDAL, GDCM, FFmpeg, GStreamer, ...; none is
# used to read PNG/JPEG or by any command run.sh runs) are replaced by generated stubs with the same
# soname and symbols, each of which aborts with a message naming itself if it is ever called
# (scripts/gpu-bundle-trim.py): 41 MB instead of about 270.
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
build_dir=$repo/build
datasets=$repo/../shared/datasets
do_build=1 trim=1 out=""
usage() { sed -n '2,/^set -euo/p' "${BASH_SOURCE[0]}" | sed '$d; s/^# \{0,1\}//'; }
while [[ $# -gt 0 ]]; do
  case "$1" in
    --build-dir) build_dir=$2; shift 2 ;;
    --build-dir=*) build_dir=${1#*=}; shift ;;
    --no-build) do_build=0; shift ;;
    --datasets) datasets=$2; shift 2 ;;
    --datasets=*) datasets=${1#*=}; shift ;;
    --full) trim=0; shift ;;
    -h|--help) usage; exit 0 ;;
    -*) echo "gpu-bundle.sh: unknown option $1" >&2; exit 2 ;;
    *) [[ -z "$out" ]] || { echo "gpu-bundle.sh: one DIR only" >&2; exit 2; }; out=$1; shift ;;
  esac
done
[[ -n "$out" ]] || { usage >&2; exit 2; }
[[ "$(uname -m)" == x86_64 ]] || echo "gpu-bundle.sh: warning: this machine is $(uname -m), the bundle is for it, not x86-64" >&2
build_dir=$(cd "$build_dir" 2>/dev/null && pwd || echo "$build_dir")

if [[ $do_build == 1 ]]; then
  if [[ ! -f "$build_dir/CMakeCache.txt" ]]; then
    cmake -S "$repo" -B "$build_dir" -G Ninja -DCMAKE_BUILD_TYPE=Release -DELLIPSEKIT_BUILD_PYTHON=OFF >/dev/null
  fi
  cmake --build "$build_dir" -j2 --target ellipsekit_cli ellipsekit_bench
fi
programs=("$build_dir/bin/ellipsekit" "$build_dir/bin/ellipsekit_bench")
for p in "${programs[@]}"; do
  [[ -x "$p" ]] || { echo "gpu-bundle.sh: $p not found (build ellipsekit_cli and ellipsekit_bench)" >&2; exit 1; }
done
grep -q '^ELLIPSEKIT_WITH_VULKAN:BOOL=OFF' "$build_dir/CMakeCache.txt" 2>/dev/null &&
  echo "gpu-bundle.sh: warning: $build_dir was configured without Vulkan" >&2
vulkaninfo_bin=$(command -v vulkaninfo || true)
[[ -n "$vulkaninfo_bin" ]] && programs+=("$vulkaninfo_bin")
[[ -d "$datasets" ]] || { echo "gpu-bundle.sh: no datasets folder $datasets" >&2; exit 1; }

# The machine's own: glibc (by soname), the Vulkan loader, the GPU driver (never linked directly).
is_system() {
  case "$1" in
    linux-vdso.so.*|ld-linux*.so.*|libc.so.*|libm.so.*|libpthread.so.*|libdl.so.*|librt.so.*) return 0 ;;
    libresolv.so.*|libutil.so.*|libnsl.so.*|libanl.so.*|libmvec.so.*|libBrokenLocale.so.*) return 0 ;;
    libthread_db.so.*|libnss_*|libc_malloc_debug.so.*|libmemusage.so|libpcprofile.so) return 0 ;;
    libvulkan.so.*|libGLX_*|libEGL_*|libnvidia-*|libcuda.so.*) return 0 ;;
  esac
  return 1
}
is_compat() {
  case "$1" in libstdc++.so.*|libgcc_s.so.*|libGLX.so.*|libGLdispatch.so.*) return 0 ;; esac
  return 1
}

rm -rf "$out"
mkdir -p "$out/bin" "$out/lib/compat" "$out/loader" "$out/work" "$out/shared/datasets"
out=$(cd "$out" && pwd)
for p in "${programs[@]}"; do cp -L "$p" "$out/bin/"; done

# soname -> path, over the union of the programs' closures.
declare -A libs=()
while read -r name path; do
  is_system "$name" || libs[$name]=$path
done < <(for p in "${programs[@]}"; do ldd "$p"; done | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3}' | sort -u)
for name in "${!libs[@]}"; do
  if is_compat "$name"; then cp -L "${libs[$name]}" "$out/lib/compat/$name"; else cp -L "${libs[$name]}" "$out/lib/$name"; fi
done

# The Vulkan loader, for a machine without one (run.sh decides).
loader=$(ldconfig -p 2>/dev/null | awk '$1 == "libvulkan.so.1" && /x86-64/ && !f {print $NF; f = 1}' || true)
if [[ -n "$loader" && -f "$loader" ]]; then
  cp -L "$loader" "$out/loader/libvulkan.so.1"
  loader_version=$( (dpkg-query -W -f '${Version}' libvulkan1 2>/dev/null || true) )
  echo "libvulkan.so.1 from $(readlink -f "$loader") ${loader_version:+(Debian libvulkan1 $loader_version)}" >"$out/loader/SOURCE"
else
  echo "gpu-bundle.sh: note: no Vulkan loader here to put in loader/ (the target must have one)" >&2
fi

if [[ $trim == 1 ]]; then
  for t in python3 cc readelf; do
    command -v $t >/dev/null || { echo "gpu-bundle.sh: trimming needs $t (or use --full)" >&2; exit 1; }
  done
  python3 "$repo/scripts/gpu-bundle-trim.py" "$out"
fi

# The shared images, laid out so that ../shared/datasets from work/ is the bundle's copy.
for d in "$datasets"/*/; do
  d=${d%/}
  [[ -d "$d/images" ]] || continue
  mkdir -p "$out/shared/datasets/$(basename "$d")"
  cp -r "$d/images" "$out/shared/datasets/$(basename "$d")/"
done

# What the bundle needs of the machine: the newest glibc symbol version any bundled file asks for.
glibc_needed=$(for f in "$out"/bin/* "$out"/lib/*.so* "$out"/lib/compat/*.so*; do
                 objdump -T "$f" 2>/dev/null | grep -o 'GLIBC_[0-9][0-9.]*' || true
               done | sed 's/GLIBC_//' | sort -uV | tail -1)
{
  echo "built_on=$(uname -srm) $( (. /etc/os-release && echo "$PRETTY_NAME") 2>/dev/null || true)"
  echo "built_at=$(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)$(git -C "$repo" diff --quiet HEAD 2>/dev/null || echo +local-changes)"
  echo "glibc_needed=${glibc_needed:-unknown}"
  echo "trimmed=$trim"
} >"$out/MANIFEST"
cp "$repo/scripts/gpu-bundle-run.sh" "$out/run.sh"
chmod +x "$out/run.sh"
echo "gpu-bundle.sh: $out: $(du -sh "$out" | cut -f1), $(find "$out/lib" -type f -name '*.so*' | wc -l) libraries, needs glibc >= ${glibc_needed:-?}; run: $out/run.sh"

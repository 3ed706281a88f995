#!/usr/bin/env bash
# Run by ctest (tests/install/CMakeLists.txt): proves the installed package is usable on its own.
#   1. cmake --install <build dir> --prefix <work dir>/prefix
#   2. configure, build and run consumer/ with find_package(ellipsekit) and CMAKE_PREFIX_PATH=<prefix>
#   3. compile the same main.cc with `pkg-config --cflags --libs ellipsekit` and run it
#   (each twice: the detector consumer main.cc, and robot_main.cc against ellipsekit::robot /
#   pkg-config ellipsekit-robot)
# The work dir is recreated on each run and left in place for inspection.
set -euo pipefail

build_dir="" work_dir="" consumer_dir="" cmake_cmd=cmake generator="" make_program=""
cxx=c++ cxx_flags="" linker_flags="" build_type=Release
for arg in "$@"; do
  case "$arg" in
    --build-dir=*) build_dir=${arg#*=} ;;
    --work-dir=*) work_dir=${arg#*=} ;;
    --consumer-dir=*) consumer_dir=${arg#*=} ;;
    --cmake=*) cmake_cmd=${arg#*=} ;;
    --generator=*) generator=${arg#*=} ;;
    --make-program=*) make_program=${arg#*=} ;;
    --cxx=*) cxx=${arg#*=} ;;
    --cxx-flags=*) cxx_flags=${arg#*=} ;;
    --linker-flags=*) linker_flags=${arg#*=} ;;
    --build-type=*) build_type=${arg#*=} ;;
    *) echo "install_consumer.sh: unknown argument: $arg" >&2; exit 2 ;;
  esac
done
if [[ -z "$build_dir" || -z "$work_dir" || -z "$consumer_dir" ]]; then
  echo "install_consumer.sh: --build-dir, --work-dir and --consumer-dir are required" >&2
  exit 2
fi

fail() { echo "install_consumer: FAIL: $*" >&2; exit 1; }
# Runs a command quietly; on failure shows its output.
run_logged() {
  local log=$1; shift
  if ! "$@" >"$log" 2>&1; then
    cat "$log" >&2
    fail "command failed: $*"
  fi
}

prefix="$work_dir/prefix"
rm -rf "$work_dir"
mkdir -p "$work_dir"

echo "== cmake --install $build_dir --prefix $prefix"
run_logged "$work_dir/install.log" "$cmake_cmd" --install "$build_dir" --prefix "$prefix"
[[ -f "$prefix/include/ellipsekit/ellipsekit.h" ]] || fail "headers not installed"
config=$(find "$prefix" -name ellipsekitConfig.cmake -print -quit)
version_file=$(find "$prefix" -name ellipsekitConfigVersion.cmake -print -quit)
pc_file=$(find "$prefix" -name ellipsekit.pc -print -quit)
lib_file=$(find "$prefix" \( -name 'libellipsekit.a' -o -name 'libellipsekit.so*' \) -print -quit)
[[ -n "$config" ]] || fail "ellipsekitConfig.cmake not installed"
[[ -n "$version_file" ]] || fail "ellipsekitConfigVersion.cmake not installed"
[[ -n "$pc_file" ]] || fail "ellipsekit.pc not installed"
[[ -n "$lib_file" ]] || fail "libellipsekit not installed"
echo "   ${lib_file#"$prefix"/}, ${config#"$prefix"/}, ${pc_file#"$prefix"/}"
# Only matters for a shared build (-DBUILD_SHARED_LIBS=ON): the pkg-config binary has no rpath.
lib_dir=$(dirname "$lib_file")
export LD_LIBRARY_PATH="$lib_dir${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"

echo "== find_package(ellipsekit) consumer"
consumer_build="$work_dir/cmake-consumer"
configure=("$cmake_cmd" -S "$consumer_dir" -B "$consumer_build"
  "-DCMAKE_PREFIX_PATH=$prefix"
  -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF
  "-DCMAKE_BUILD_TYPE=$build_type"
  "-DCMAKE_CXX_COMPILER=$cxx"
  "-DCMAKE_CXX_FLAGS=$cxx_flags"
  "-DCMAKE_EXE_LINKER_FLAGS=$linker_flags")
if [[ -n "$generator" ]]; then configure+=(-G "$generator"); fi
if [[ -n "$make_program" ]]; then configure+=("-DCMAKE_MAKE_PROGRAM=$make_program"); fi
run_logged "$work_dir/cmake-configure.log" "${configure[@]}"
# The package must come from the prefix, not from a system copy or the build tree.
found_dir=$(sed -n 's/^ellipsekit_DIR:[A-Z]*=//p' "$consumer_build/CMakeCache.txt")
[[ "$found_dir" == "$prefix"/* ]] || fail "find_package found ellipsekit in '$found_dir', not under $prefix"
run_logged "$work_dir/cmake-build.log" "$cmake_cmd" --build "$consumer_build"
"$consumer_build/ellipsekit_consumer" || fail "find_package consumer exited with $?"
[[ -f "$prefix/include/ellipsekit/robot/frame_loop.h" ]] || fail "robot headers not installed"
"$consumer_build/ellipsekit_robot_consumer" || fail "find_package robot consumer (ellipsekit::robot) exited with $?"

echo "== pkg-config consumer"
command -v pkg-config >/dev/null || fail "pkg-config not found"
pc_dir=$(dirname "$pc_file")
export PKG_CONFIG_PATH="$pc_dir${PKG_CONFIG_PATH:+:$PKG_CONFIG_PATH}"
pc_flags=$(pkg-config --cflags --libs ellipsekit) || fail "pkg-config --cflags --libs ellipsekit failed"
echo "   pkg-config --cflags --libs ellipsekit: $pc_flags"
read -ra pc_args <<<"$pc_flags"
read -ra extra_cxx <<<"$cxx_flags"
read -ra extra_ld <<<"$linker_flags"
run_logged "$work_dir/pkgconfig-build.log" \
  "$cxx" -std=c++20 "${extra_cxx[@]}" "$consumer_dir/main.cc" -o "$work_dir/pkgconfig-consumer" \
  "${pc_args[@]}" "${extra_ld[@]}"
"$work_dir/pkgconfig-consumer" || fail "pkg-config consumer exited with $?"
robot_flags=$(pkg-config --cflags --libs ellipsekit-robot) || fail "pkg-config --cflags --libs ellipsekit-robot failed"
echo "   pkg-config --cflags --libs ellipsekit-robot: $robot_flags"
read -ra robot_args <<<"$robot_flags"
run_logged "$work_dir/pkgconfig-robot-build.log" \
  "$cxx" -std=c++20 "${extra_cxx[@]}" "$consumer_dir/robot_main.cc" -o "$work_dir/pkgconfig-robot-consumer" \
  "${robot_args[@]}" "${extra_ld[@]}"
"$work_dir/pkgconfig-robot-consumer" || fail "pkg-config robot consumer exited with $?"

echo "install_consumer: PASS"

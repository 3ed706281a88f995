#!/usr/bin/env bash
# Installs the Debian packages ellipsekit needs to build, test and benchmark.
# Idempotent: when everything is present it only asks dpkg and exits (well under a second).
# Runs apt-get as root; otherwise prints the exact command to run with sudo and exits 1.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libopencv-dev libopencv-contrib-dev libeigen3-dev libhwy-dev
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers glslang-tools spirv-tools
  libgtest-dev libbenchmark-dev python3
  python3-dev pybind11-dev python3-numpy python3-distributed python3-pytest python3-tqdm  # python/
  clang libclang-rt-14-dev  # scripts/fuzz.sh (libFuzzer)
)

# One dpkg-query for all packages; db:Status-Status is "installed" only for a fully installed package
# (not "config-files", "half-installed", ...). Unknown packages are simply absent from its output.
declare -A installed=()
while read -r name status; do
  if [[ "$status" == "installed" ]]; then installed[$name]=1; fi
done < <(dpkg-query -W -f='${Package} ${db:Status-Status}\n' "${packages[@]}" 2>/dev/null || true)

missing=()
for pkg in "${packages[@]}"; do
  if [[ -z "${installed[$pkg]:-}" ]]; then
    missing+=("$pkg")
  fi
done

if [[ ${#missing[@]} -eq 0 ]]; then
  exit 0
fi

echo "setup.sh: missing Debian packages: ${missing[*]}" >&2
if [[ $(id -u) -ne 0 ]]; then
  echo "setup.sh: not root; run:" >&2
  echo "  sudo apt-get update && sudo apt-get install -y --no-install-recommends ${missing[*]}" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
# -qq keeps apt quiet; errors still go to stderr and fail the script (set -e).
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "setup.sh: installed ${missing[*]}" >&2

#!/usr/bin/env bash
# Builds ellipsekit (Release, into build/) and runs the demo: scripts/demo.sh [demo options...]
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

scripts/setup.sh
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
cmake --build build -j2 --target ellipsekit_cli  # only the program the demo runs (not the tests, benchmarks or Python module)
exec build/bin/ellipsekit demo "$@"

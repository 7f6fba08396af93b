#!/usr/bin/env bash
# Development build in build/dev: the extension lands in python/drillpy, so
#   PYTHONPATH=python python3 -m pytest tests/python     and    ctest --test-dir build/dev
# run against the working tree without installing.
set -euo pipefail
cd "$(dirname "$0")/.."
cmake -S . -B build/dev -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRILLPY_BUILD_TESTS=ON \
  -Dpybind11_DIR="$(python3 -m pybind11 --cmakedir)" >/dev/null
cmake --build build/dev -j"${JOBS:-2}"

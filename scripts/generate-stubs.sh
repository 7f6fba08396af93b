#!/usr/bin/env bash
# Regenerate the type stubs of the engine module, python/drillpy/_core.pyi, from the built module
# (build it first: cmake --build build/dev --target _core) with pybind11-stubgen.
#
#   scripts/generate-stubs.sh [OUTPUT_FILE]     (default: python/drillpy/_core.pyi)
#
# PYTHON selects the interpreter (default: python3). tests/python/test_stubs.py regenerates the
# stubs into a temporary file and checks that the checked-in file is current.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=${1:-"$root/python/drillpy/_core.pyi"}
python=${PYTHON:-python3}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# The development build puts the module next to the sources; an installed package has it in
# site-packages (then the sources, which lack it, must not shadow it).
if compgen -G "$root/python/drillpy/_core*.so" >/dev/null; then
  export PYTHONPATH="$root/python${PYTHONPATH:+:$PYTHONPATH}"
fi
PYTHONWARNINGS=ignore \
  "$python" -m pybind11_stubgen drillpy._core --exit-code -o "$tmp" >"$tmp/log" 2>&1 ||
  { cat "$tmp/log" >&2; exit 1; }
cp "$tmp/drillpy/_core.pyi" "$out"

#!/usr/bin/env bash
# Regenerate the configuration's JSON Schema, python/drillpy/model/config.schema.json, from
# `drillsim --schema` (it is written from the table of keys that the engine's parser accepts,
# cpp/include/drill/config.hpp). Build drillsim first: cmake --build build/dev --target drillsim.
#
#   scripts/generate-schema.sh [DRILLSIM]     (default: $DRILLSIM, else build/dev/drillsim)
#
# tests/python/test_schema.py checks that the checked-in file is current.
set -euo pipefail

root=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
drillsim=${1:-${DRILLSIM:-"$root/build/dev/drillsim"}}
out="$root/python/drillpy/model/config.schema.json"

"$drillsim" --schema >"$out.tmp"
mv "$out.tmp" "$out"

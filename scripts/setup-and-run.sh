#!/usr/bin/env bash
# Fresh machine -> everything installed -> the main job on the thesis-field preset.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
export PIP_BREAK_SYSTEM_PACKAGES=1 PIP_ROOT_USER_ACTION=ignore
python3 -m pip install -q --disable-pip-version-check .
drillpy report --preset thesis-field --out results/thesis-field

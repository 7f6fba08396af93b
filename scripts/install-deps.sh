#!/usr/bin/env bash
# Install what a fresh Debian 12 machine (root, Python 3.11) lacks to build and test drillpy.
set -euo pipefail
export DEBIAN_FRONTEND=noninteractive PIP_BREAK_SYSTEM_PACKAGES=1 PIP_ROOT_USER_ACTION=ignore
pkgs="g++ make cmake ninja-build git libeigen3-dev libgtest-dev googletest nlohmann-json3-dev librandom123-dev pybind11-dev libcli11-dev libhwy-dev"
python3 -m pip --version >/dev/null 2>&1 || pkgs="$pkgs python3-pip python3-dev"
# scripts/smoke-venv.sh makes a virtual environment (Debian splits ensurepip into python3-venv)
python3 -c "import ensurepip" >/dev/null 2>&1 || pkgs="$pkgs python3-venv"
missing=""
for p in $pkgs; do dpkg -s "$p" >/dev/null 2>&1 || missing="$missing $p"; done
if [ -n "$missing" ]; then
  echo "apt-get install:$missing"
  apt-get update -qq
  apt-get install -y -qq --no-install-recommends $missing >/dev/null
fi
python3 -m pip install -q --disable-pip-version-check numpy scipy matplotlib tqdm scikit-learn threadpoolctl xarray zarr 'dask[distributed]' pytest scikit-build-core pybind11 ruff pybind11-stubgen==3.0.0 hypothesis jsonschema \
  build sphinx myst-parser sphinx-gallery numpydoc

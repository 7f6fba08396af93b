#!/usr/bin/env bash
# The whole test suite on a fresh machine: install what is missing, build and install the package,
# build the C++ tests, run ctest and pytest.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
python3 -m ruff check python tests benchmarks scripts
export PIP_BREAK_SYSTEM_PACKAGES=1 PIP_ROOT_USER_ACTION=ignore
python3 -m pip install -q --disable-pip-version-check .
cmake -S . -B build/ctest -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRILLPY_BUILD_PYTHON=OFF -DDRILLPY_BUILD_TESTS=ON >/dev/null
cmake --build build/ctest -j2
ctest --test-dir build/ctest --output-on-failure -j2
cd tests && DRILLSIM="$(cd .. && pwd)/build/ctest/drillsim" python3 -m pytest -q python

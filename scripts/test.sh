#!/usr/bin/env bash
# The whole test suite on a fresh machine: install what is missing; build the sdist and the wheel
# and smoke-test the wheel in a fresh venv (scripts/smoke-venv.sh); install that wheel; build the
# C++ tests and run ctest and pytest; run the rounding-sensitive tests (the loop, its calibration,
# the identification) again under another OpenBLAS kernel and one BLAS thread; build the
# documentation with warnings as errors (its gallery executes the tutorials).
set -euo pipefail
cd "$(dirname "$0")/.."
step() { printf '\n== %s (%s)\n' "$1" "$(date -u +%H:%M:%S)"; }
step "dependencies"
bash scripts/install-deps.sh
python3 -m ruff check python tests benchmarks scripts docs
export PIP_BREAK_SYSTEM_PACKAGES=1 PIP_ROOT_USER_ACTION=ignore PIP_DISABLE_PIP_VERSION_CHECK=1

step "sdist, wheel and the fresh-venv smoke test"
bash scripts/smoke-venv.sh dist
# The distribution is drillpy-torsion; a distribution named drillpy (this package under its old
# name, or PyPI's unrelated Apache Drill client) would own the same top-level `drillpy` module.
python3 -m pip uninstall -q -y drillpy >/dev/null 2>&1 || true
python3 -m pip install -q --force-reinstall --no-deps dist/drillpy_torsion-*.whl

step "ctest"
cmake -S . -B build/ctest -G Ninja -DCMAKE_BUILD_TYPE=Release -DDRILLPY_BUILD_PYTHON=OFF -DDRILLPY_BUILD_TESTS=ON >/dev/null
cmake --build build/ctest -j2
ctest --test-dir build/ctest --output-on-failure -j2

step "pytest"
cd tests
DRILLSIM="$(cd .. && pwd)/build/ctest/drillsim" python3 -m pytest -q python

# The decisions and fits of the loop and of the identification go through LAPACK/BLAS and
# least-squares paths whose rounding depends on the CPU's kernel and the thread count: run them
# again on a pre-AVX2 kernel with one BLAS thread (the first run: this CPU's kernel, 2 threads).
CORE=${DRILLPY_SECOND_CORETYPE:-Sandybridge}
step "rounding-sensitive tests again: OPENBLAS_CORETYPE=$CORE, one BLAS thread"
export OPENBLAS_CORETYPE=$CORE OPENBLAS_NUM_THREADS=1
python3 - "$CORE" <<'EOF'
import sys
import numpy, scipy.linalg  # noqa: F401  (both carry an OpenBLAS)
from threadpoolctl import threadpool_info
blas = [i for i in threadpool_info() if i["internal_api"] == "openblas"]
assert blas and all(i["architecture"] == sys.argv[1] and i["num_threads"] == 1 for i in blas), blas
print("OpenBLAS:", ", ".join(f"{i['prefix']} {i['version']} {i['architecture']} x{i['num_threads']}" for i in blas))
EOF
python3 -m pytest -q -p no:cacheprovider python/test_loop.py python/test_loop_calibration.py python/test_loop_discovery.py python/test_loop_gate.py \
  python/test_loop_effects.py python/test_identification.py python/test_loop_fluctuation.py python/test_loop_refit.py
unset OPENBLAS_CORETYPE OPENBLAS_NUM_THREADS
cd ..

step "documentation (sphinx -W, the gallery executed)"
rm -rf docs/api docs/auto_examples build/docs
start=$(date +%s)
python3 -m sphinx -W --keep-going -q -b html docs build/docs/html
echo "documentation built in $(( $(date +%s) - start )) s: build/docs/html/index.html"
step "done"

#!/usr/bin/env bash
# Build the sdist and the wheel with `python3 -m build` (the wheel from the sdist, so the sdist is
# proved complete), install the wheel into a fresh virtual environment that does not see the
# source tree or the system's site-packages, and run a smoke test there from an empty directory:
# the distribution's name and metadata, `import drillpy` from the venv, the engine module, the
# `drillpy` command and one short run of the engine against a number of the thesis.
#
#   bash scripts/smoke-venv.sh [DIST_DIR]      # DIST_DIR (default dist/) keeps the sdist and wheel
#
# scripts/test.sh runs it once and then installs the same wheel for the test suite.
set -euo pipefail
cd "$(dirname "$0")/.."
export PIP_DISABLE_PIP_VERSION_CHECK=1 PIP_ROOT_USER_ACTION=ignore
dist="$(mkdir -p "${1:-dist}" && cd "${1:-dist}" && pwd)"
rm -f "$dist"/drillpy_torsion-*
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

t0=$(date +%s)
python3 -m build --outdir "$dist" . >"$work/build.log" 2>&1 || { tail -40 "$work/build.log"; exit 1; }
sdist=$(ls "$dist"/drillpy_torsion-*.tar.gz)
wheel=$(ls "$dist"/drillpy_torsion-*.whl)
echo "built $(basename "$sdist") and $(basename "$wheel") in $(( $(date +%s) - t0 )) s"

python3 -m venv "$work/venv"
"$work/venv/bin/python" -m pip install -q "$wheel"
mkdir "$work/empty"
cd "$work/empty"   # neither the source tree nor its python/ directory is on the path
PYTHONPATH= "$work/venv/bin/python" - "$work/venv" <<'EOF'
import json
import subprocess
import sys
from importlib import metadata
from pathlib import Path

venv = Path(sys.argv[1]).resolve()
meta = metadata.metadata("drillpy-torsion")
assert meta["Name"] == "drillpy-torsion", meta["Name"]
assert meta["License-Expression"] == "MIT", meta["License-Expression"]
assert any(c.startswith("Topic :: Scientific/Engineering") for c in meta.get_all("Classifier"))
assert meta["Description-Content-Type"] == "text/markdown" and "drill strings" in meta["Description"]
import drillpy
from drillpy import _core
here = Path(drillpy.__file__).resolve()
assert venv in here.parents, f"drillpy imported from {here}, not from the venv"
assert drillpy.__version__ == metadata.version("drillpy-torsion"), (drillpy.__version__, metadata.version("drillpy-torsion"))
print(f"drillpy-torsion {drillpy.__version__}: import drillpy from {here.parent}, engine {Path(_core.__file__).name}")

cmd = venv / "bin" / "drillpy"
out = subprocess.run([str(cmd), "--version"], capture_output=True, text=True, check=True).stdout.strip()
assert out == f"drillpy {drillpy.__version__}", out
f = json.loads(subprocess.run([str(cmd), "modes", "--preset", "thesis-rig", "-n", "1", "--json"],
                              capture_output=True, text=True, check=True).stdout)["frequencies_hz"][0]
assert abs(f - 2.89) < 0.01, f  # Table 5.1's rig: first mode 2.89 Hz
print(f"{out}; drillpy modes --preset thesis-rig: first mode {f:.4f} Hz (thesis 2.89)")

cfg = drillpy.with_overrides(drillpy.load_config(preset="thesis-field"), elements=20, modes=5)
run = drillpy.simulate(cfg, top_speed=10.0)
assert run.severity > 0.5 and len(run.stick_durations) > 0, run.severity  # stick-slip at 10 rad/s (SS > 0.5 below 19.7)
print(f"drillpy.simulate(thesis-field, 20 elements, 5 modes, 10 rad/s): SS {run.severity:.3f}, "
      f"{len(run.stick_durations)} sticks: stick-slip, as below the 19.7 rad/s threshold")
EOF
echo "smoke test passed in a fresh venv ($(( $(date +%s) - t0 )) s in all)"

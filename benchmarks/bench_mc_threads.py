"""``drillpy mc`` as a user runs it, on 1 thread against 2 (issue 33: the 2-thread speed-up of a run of
about 5 s, the process's start and imports included), measured in one run.

    PYTHONPATH=python python3 benchmarks/bench_mc_threads.py [--samples 240] [--repeats 5]

Runs ``python -m drillpy mc --preset thesis-field --samples N --speeds 10:24:8 --duration 100
--no-figures --no-progress --out DIR`` with ``--threads 1`` and ``--threads 2`` alternately,
``--repeats`` times each, and prints every wall time, the medians and their ratio, and whether the
two thread counts wrote the same severities (``mc.json``: the same seed gives the same numbers
whatever the thread count). Choose ``--samples`` so that the 2-thread run takes about 5 s on your
machine. The machine is shared: read the ratio of the medians.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]


def run(threads: int, samples: int, out: str) -> float:
    env = dict(os.environ)
    if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
        env["PYTHONPATH"] = str(REPO / "python")
    cmd = [sys.executable, "-m", "drillpy", "mc", "--preset", "thesis-field", "--samples", str(samples),
           "--speeds", "10:24:8", "--duration", "100", "--threads", str(threads), "--no-figures", "--no-progress",
           "--out", out]
    t0 = time.perf_counter()
    subprocess.run(cmd, check=True, env=env, capture_output=True)
    return time.perf_counter() - t0


def severities(out: str):
    with open(os.path.join(out, "mc.json")) as fh:
        d = json.load(fh)
    d.pop("provenance", None)
    return d


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=240)
    ap.add_argument("--repeats", type=int, default=5)
    a = ap.parse_args()
    walls: dict = {1: [], 2: []}
    with tempfile.TemporaryDirectory() as tmp:
        for r in range(a.repeats):
            for th in (1, 2):
                out = os.path.join(tmp, f"t{th}_{r}")
                walls[th].append(run(th, a.samples, out))
                print(f"repeat {r + 1}, {th} thread{'s' if th > 1 else ''}: {walls[th][-1]:.2f} s", flush=True)
        same = severities(os.path.join(tmp, "t1_0")) == severities(os.path.join(tmp, "t2_0"))
    m1, m2 = statistics.median(walls[1]), statistics.median(walls[2])
    print(f"\ndrillpy mc, thesis-field, {a.samples} samples x 8 speeds, 100 s runs; load average "
          f"{os.getloadavg()[0]:.1f}")
    print(f"median wall: 1 thread {m1:.2f} s, 2 threads {m2:.2f} s; speed-up {m1 / m2:.2f} x (target >= 1.85)")
    print(f"the same mc.json on 1 and 2 threads: {same}")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())

"""Every benchmark behind docs/numerics.md's table of measured speed-ups, run one after the other on
one machine (issue 33: the table regenerated in one sitting, the machine named).

    PYTHONPATH=python python3 benchmarks/numerics_table.py --out DIR [--only NAME,...] [--base-tree BASE]

Runs each benchmark script in its own process with its documented arguments, writes its whole
output to ``DIR/NAME.txt`` and prints, per benchmark, the machine's load average before and after
and the wall time; the figures of the table are read from those files. The first lines name the
machine: the processor (``/proc/cpuinfo``), the cores, the engine's SIMD width (runs per batch) and
the Python and drillpy in use. ``--base-tree`` (a source tree with its own built extension, see
``bench_loop.py``) adds the loop's ``base`` configuration. The whole set took 28 minutes on a 2-core
AMD EPYC at load 0.6-4.5 (the per-benchmark wall times it printed: 3, 1269, 103, 5, 96, 102 and 99 s),
most of it the Fig. 4.9 study; the machine is shared, so each ratio is measured within one benchmark's run.
"""
from __future__ import annotations

import argparse
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
HERE = Path(__file__).resolve().parent

#: name -> the benchmark's arguments (the rows of docs/numerics.md's table, in its order)
BENCHMARKS = {
    "batched": ["bench_batched.py"],
    "fig49": ["bench_fig49.py", "--samples", "500", "--exact-dt", "5"],
    "loop_sample175": ["loop_sample175.py"],
    "damping_scan": ["bench_damping_scan.py", "--repeats", "7"],
    "loop": ["bench_loop.py"],
    "loop_timestep": ["loop_timestep.py", "--only", "sample175"],
    "mc_threads": ["bench_mc_threads.py", "--repeats", "5"],
}


def processor() -> str:
    """The processor's model name and widest vector extension (``/proc/cpuinfo``), or the platform's description."""
    name, flags = platform.processor() or platform.machine(), set()
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            key, _, value = line.partition(":")
            if key.strip() == "model name":
                name = value.strip()
            elif key.strip() == "flags":
                flags = set(value.split())
    except OSError:
        pass
    isa = next((label for flag, label in (("avx512f", "AVX-512"), ("avx2", "AVX2")) if flag in flags), None)
    return f"{name} ({isa})" if isa else name


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, required=True, help="folder for each benchmark's output")
    ap.add_argument("--only", default="", help=f"comma-separated names among {', '.join(BENCHMARKS)}")
    ap.add_argument("--base-tree", type=Path, help="bench_loop.py's base tree (the loop before issue 33)")
    a = ap.parse_args()
    names = [n for n in a.only.split(",") if n] or list(BENCHMARKS)
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        ap.error(f"--only: unknown benchmark {unknown[0]!r} (known: {', '.join(BENCHMARKS)})")
    a.out.mkdir(parents=True, exist_ok=True)
    env = dict(os.environ)
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        env["PYTHONPATH"] = os.pathsep.join([str(REPO / "python")] + [p for p in [env.get("PYTHONPATH")] if p])
    probe = subprocess.run([sys.executable, "-c", "import drillpy; from drillpy import _core; "
                            "print(drillpy.__file__, _core.Simulation.batch_width())"],
                           env=env, capture_output=True, text=True, check=True).stdout.split()
    print(f"machine: {processor()}, {os.cpu_count()} cores, {probe[1]} runs per SIMD batch; "
          f"Python {platform.python_version()}; drillpy from {Path(probe[0]).parent}")
    for name in names:
        argv = [sys.executable, str(HERE / BENCHMARKS[name][0]), *BENCHMARKS[name][1:]]
        if name == "loop" and a.base_tree:
            argv += ["--base-tree", str(a.base_tree)]
        load0, t0 = os.getloadavg()[0], time.perf_counter()
        with open(a.out / f"{name}.txt", "w") as f:
            rc = subprocess.run(argv, env=env, stdout=f, stderr=subprocess.STDOUT, cwd=REPO).returncode
        wall = time.perf_counter() - t0
        print(f"{name}: {' '.join(BENCHMARKS[name])}: {wall:.0f} s, load {load0:.1f} -> {os.getloadavg()[0]:.1f}"
              f"{'' if rc == 0 else f', FAILED (exit {rc})'}: {a.out / (name + '.txt')}")
        sys.stdout.flush()
        if rc:
            return rc
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Dask overhead and memory of a stored study (issue 14), measured side by side in one run.

    PYTHONPATH=python python3 benchmarks/bench_distributed.py [--samples 500] [--workers 2]

1. The Fig. 4.9 study (thesis-field, 22 speeds 6-27 rad/s, drillpy mc's protocol: 100 s shared warm
   start, 60 s with eta, SS over the last 40 s; ``--samples``, 500 by default as in the thesis) run
   with the local backend (OpenMP, ``--workers`` threads) and with Dask on a LocalCluster of
   ``--workers`` single-threaded workers, both streaming to a Zarr store. Printed: wall times, the
   cluster's start-up, the overhead of Dask with and without the start-up, and whether both stores
   hold the same bits.
2. Memory: the peak resident memory of a stored study of 500 and of 2000 samples (short runs, each
   in a fresh process): flat in the number of samples when results stream to the store.
"""
from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))


def fig49_study(samples: int, **durations):
    from drillpy.model.config import load_config, with_overrides
    from drillpy.study import Study
    from drillpy.uncertainty import montecarlo as mcm
    from drillpy.uncertainty.process import THESIS_PSD
    import numpy as np
    d = {"warmup": mcm.WARMUP_S, "duration": mcm.DURATION_S, "transient": mcm.TRANSIENT_S, **durations}
    cfg = with_overrides(load_config(preset="thesis-field"), duration=d["duration"], transient=d["transient"])
    speeds = tuple(float(x) for x in np.linspace(6.0, 27.0, d.get("speeds", 22)))
    return Study("mc", cfg, speeds, samples=samples, seed=1,
                 options={"psd": THESIS_PSD.as_dict(), "eta_dt_s": mcm.ETA_DT_S, "warmup_s": d["warmup"]})


def _memory_child(samples: int, out: str) -> None:
    from drillpy.study import run_study
    study = fig49_study(samples, warmup=10.0, duration=20.0, transient=10.0, speeds=4)
    run_study(study, out, chunk=50, threads=2, progress=False)
    print(json.dumps({"maxrss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0}))


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--samples", type=int, default=500)
    ap.add_argument("--workers", type=int, default=2)
    ap.add_argument("--memory-child", type=int, help=argparse.SUPPRESS)
    ap.add_argument("--out", help=argparse.SUPPRESS)
    a = ap.parse_args()
    if a.memory_child:
        _memory_child(a.memory_child, a.out)
        return 0
    import numpy as np
    from dask.distributed import Client, LocalCluster
    from drillpy.study import run_study
    study = fig49_study(a.samples)
    tmp = Path(tempfile.mkdtemp(prefix="bench_distributed_"))
    print(f"Fig. 4.9 study: {a.samples} samples x {len(study.top_speeds)} speeds, thesis-field, mc protocol "
          f"(100 s warm start + 60 s), {a.workers} cores")
    t0 = time.perf_counter()
    local = run_study(study, tmp / "local", threads=a.workers, progress=False)
    t_local = time.perf_counter() - t0
    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=a.workers, threads_per_worker=1, processes=True, dashboard_address=":0")
    client = Client(cluster)
    t_start = time.perf_counter() - t0
    t0 = time.perf_counter()
    dask = run_study(study, tmp / "dask", client=client, progress=False)
    t_dask = time.perf_counter() - t0
    client.close()
    cluster.close()
    same = bool(np.array_equal(local["severity"].values, dask["severity"].values))
    print(f"local (OpenMP, {a.workers} threads):          {t_local:8.1f} s")
    print(f"Dask LocalCluster start-up:               {t_start:8.1f} s")
    print(f"Dask ({a.workers} workers x 1 thread), study:     {t_dask:8.1f} s")
    print(f"Dask overhead without start-up: {100 * (t_dask / t_local - 1):+.1f} %; with start-up: "
          f"{100 * ((t_dask + t_start) / t_local - 1):+.1f} %")
    print(f"identical SS arrays (local vs Dask): {same}")
    rss = {}
    for n in (500, 2000):
        r = subprocess.run([sys.executable, __file__, "--memory-child", str(n), "--out", str(tmp / f"mem{n}")],
                           capture_output=True, text=True, check=True)
        rss[n] = json.loads(r.stdout.splitlines()[-1])["maxrss_mb"]
    print(f"peak memory of a stored study (4 speeds, short runs): 500 samples {rss[500]:.0f} MB, "
          f"2000 samples {rss[2000]:.0f} MB (ratio {rss[2000] / rss[500]:.2f})")
    print(f"dask overhead: {100 * ((t_dask + t_start) / t_local - 1):.1f} %")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())

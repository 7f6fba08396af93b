"""Studies on a backend and in a Zarr store (issue 14): the same bits whatever the backend, the
workers, the chunk size, the order of completion, an interruption or an extension."""
import json

import numpy as np
import pytest
import xarray as xr

import drillpy
from drillpy.model.config import load_config, with_overrides
from drillpy.study import Study, open_study, run_study
from drillpy.study import definition, run as study_run
from drillpy.uncertainty.montecarlo import stochastic_study
from drillpy.uncertainty.process import THESIS_PSD

SPEEDS = (12.0, 18.0, 24.0)
SHORT = dict(warmup=20.0, duration=30.0, transient=10.0)


@pytest.fixture(scope="module")
def cfg():
    return with_overrides(load_config(preset="thesis-field"), modes=8)


def _mc(cfg, samples, seed=4):
    c = with_overrides(cfg, duration=SHORT["duration"], transient=SHORT["transient"])
    return Study("mc", c, SPEEDS, samples=samples, seed=seed,
                 options={"psd": THESIS_PSD.as_dict(), "eta_dt_s": 0.05, "warmup_s": SHORT["warmup"]})


@pytest.fixture(scope="module")
def reference(cfg):
    """The study run at once by the Monte Carlo module (OpenMP, one call)."""
    return stochastic_study(cfg, SPEEDS, 13, 4, threads=2, progress=False, **SHORT)


@pytest.mark.parametrize("chunk", [1, 7, 64])
def test_mc_study_is_bit_identical_for_any_chunk_and_labelled(cfg, reference, chunk, tmp_path):
    ds = run_study(_mc(cfg, 13), tmp_path, chunk=chunk, progress=False)
    np.testing.assert_array_equal(ds["severity"].values, reference.severity)
    np.testing.assert_array_equal(ds["deterministic_severity"].values, reference.deterministic)
    assert ds["severity"].dims == ("sample", "top_speed") and ds["top_speed"].attrs["units"] == "rad/s"
    assert ds.attrs["eta_std"] == reference.eta_std and ds.attrs["chunk"] == chunk
    assert json.loads(ds.attrs["study"])["seed"] == 4 and "drillpy_version" in json.loads(ds.attrs["provenance"])
    lazily = xr.open_zarr(tmp_path / "study.zarr", consolidated=False)  # what a user opens
    np.testing.assert_array_equal(lazily["severity"].values, reference.severity)
    xr.testing.assert_identical(lazily.load(), ds)  # the zarr-written store reads as the labelled study


def test_interrupted_store_resumes_with_only_the_missing_blocks(cfg, reference, tmp_path, monkeypatch):
    study = _mc(cfg, 13)
    calls = []
    real = study_run.compute_block

    def stop_at_third(s, lo, hi, threads=0):
        calls.append(lo)
        if len(calls) == 3:
            raise KeyboardInterrupt
        return real(s, lo, hi, threads)

    monkeypatch.setattr(study_run, "compute_block", stop_at_third)
    with pytest.raises(KeyboardInterrupt):
        run_study(study, tmp_path, chunk=4, progress=False)
    ds = open_study(tmp_path)
    assert ds["done"].values.tolist() == [True] * 8 + [False] * 5  # two blocks written, flagged, nothing else
    assert np.isnan(ds["severity"].values[8:]).all()
    calls.clear()
    monkeypatch.setattr(study_run, "compute_block", lambda s, lo, hi, threads=0: (calls.append(lo), real(s, lo, hi,
                                                                                                          threads))[1])
    ds = run_study(study, tmp_path, chunk=99, progress=False)  # the store keeps its chunk of 4
    assert calls == [8, 12]
    np.testing.assert_array_equal(ds["severity"].values, reference.severity)
    calls.clear()
    run_study(study, tmp_path, progress=False)
    assert calls == []  # finished: nothing to do


def test_a_finished_study_extends_and_refuses_another_study(cfg, reference, tmp_path):
    run_study(_mc(cfg, 6), tmp_path, chunk=4, progress=False)
    first = open_study(tmp_path)["severity"].values.copy()
    ds = run_study(_mc(cfg, 13), tmp_path, progress=False)
    np.testing.assert_array_equal(ds["severity"].values[:6], first)
    np.testing.assert_array_equal(ds["severity"].values, reference.severity)
    with pytest.raises(ValueError, match=r"holds another study \(seed differs\)"):
        run_study(_mc(cfg, 13, seed=5), tmp_path, progress=False)
    with pytest.raises(ValueError, match=r"samples = 6: the store .* already holds 13 samples"):
        run_study(_mc(cfg, 6), tmp_path, progress=False)


def test_sweep_and_map_studies_equal_the_engine_sweep(cfg):
    c = with_overrides(cfg, duration=40.0, transient=20.0)
    speeds, wobs = (8.0, 12.0, 16.0, 20.0, 24.0), (150e3, 245e3)
    ss = drillpy.sweep_severity(c, list(speeds), progress=False)
    for chunk in (1, 2, 5):
        ds = run_study(Study("sweep", c, speeds), chunk=chunk, progress=False)
        np.testing.assert_array_equal(ds["severity"].values, ss)
    grid = drillpy.stability_map(c, list(speeds), list(wobs), progress=False)
    ds = run_study(Study("map", c, speeds, wobs=wobs), chunk=1, progress=False)
    assert ds["severity"].dims == ("wob", "top_speed") and ds["wob"].attrs["units"] == "N"
    np.testing.assert_array_equal(ds["severity"].values, grid)


def test_dask_local_cluster_gives_the_same_bits(cfg, reference, tmp_path):
    pytest.importorskip("dask.distributed")
    lines = []
    ds = run_study(_mc(cfg, 13), tmp_path, scheduler="local:2", chunk=3, progress=False, log=lines.append)
    np.testing.assert_array_equal(ds["severity"].values, reference.severity)
    assert lines and "dashboard http" in lines[0]


@pytest.mark.parametrize("text, message", [
    ("local:0", "scheduler = 'local:0'"), ("cluster", "use local, local:N"), ("local:x", "local:x")])
def test_bad_scheduler_is_one_clear_error(text, message):
    with pytest.raises(ValueError, match=message):
        study_run.parse_scheduler(text)


def test_an_unreachable_scheduler_is_one_clear_error_within_its_timeout():
    pytest.importorskip("dask.distributed")
    import socket
    import time
    from drillpy.study.cluster import open_client
    with socket.socket() as s:  # a port of this machine that nothing listens on
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
    start = time.perf_counter()
    with pytest.raises(ValueError, match=rf"^scheduler = 'tcp://127.0.0.1:{port}': no Dask scheduler reached within 1 s"):
        open_client(f"tcp://127.0.0.1:{port}", print, timeout_s=1.0)
    assert time.perf_counter() - start < 10


def test_bad_study_definitions_name_the_field(cfg):
    with pytest.raises(ValueError, match=r"^kind = 'grid'"):
        Study("grid", cfg, SPEEDS)
    with pytest.raises(ValueError, match=r"^top_speeds = \[-1.0\]"):
        Study("sweep", cfg, (-1.0,))
    with pytest.raises(ValueError, match=r"^samples = 0"):
        _mc(cfg, 0)
    with pytest.raises(ValueError, match=r"^chunk = 0"):
        run_study(Study("sweep", cfg, SPEEDS), chunk=0, progress=False)
    assert definition.TASK_DIM == {"sweep": "top_speed", "map": "wob", "mc": "sample", "structural": "sample",
                                   "frf": "sample"}


def test_commands_store_resume_and_distribute_their_studies(tmp_path, capsys):
    """drillpy mc/sweep/map --out write study.zarr; the same mc command extended computes only the new
    samples and prints what the in-memory study prints; --scheduler local:2 gives the same JSON."""
    from drillpy.cli import main
    mc = ["mc", "--preset", "thesis-field", "--modes", "8", "--speeds", "12,18,24", "--warmup", "20", "--duration",
          "30", "--transient", "10", "--seed", "4", "--no-progress", "--json"]
    assert main([*mc, "--samples", "7"]) == 0
    in_memory = json.loads(capsys.readouterr().out)
    assert main([*mc, "--samples", "4", "--out", str(tmp_path / "mc"), "--no-figures", "--chunk", "3"]) == 0
    assert main([*mc, "--samples", "7", "--out", str(tmp_path / "mc"), "--no-figures"]) == 0
    assert json.loads(capsys.readouterr().out.splitlines()[-1]) == in_memory
    ds = open_study(tmp_path / "mc")
    assert ds.sizes["sample"] == 7 and ds.attrs["chunk"] == 3 and ds["done"].values.all()
    sweep = ["sweep", "--preset", "thesis-rig", "--speeds", "4:12:5", "--duration", "20", "--transient", "10",
             "--no-progress", "--json"]
    assert main(sweep) == 0
    plain = capsys.readouterr().out
    assert main([*sweep, "--out", str(tmp_path / "sweep"), "--chunk", "2"]) == 0
    assert capsys.readouterr().out == plain
    assert open_study(tmp_path / "sweep")["severity"].dims == ("top_speed",)
    assert main([*sweep, "--scheduler", "local:2"]) == 0
    assert capsys.readouterr().out == plain
    assert main([*sweep, "--scheduler", "cluster"]) == 2
    assert "scheduler = 'cluster'" in capsys.readouterr().err


def test_frf_and_structural_studies_equal_the_chapter6_functions(tmp_path):
    """An frf study stores every sample's FRF; the envelope from the store is frf_envelope's, bit for bit;
    a structural study (robust-ss's SM_CB2 source) stores the SS of severity_study."""
    from drillpy.uncertainty.frf import envelope_from_samples, frf_envelope, observation_nodes
    from drillpy.uncertainty.structural import severity_study
    cfg = load_config(preset="thesis-ch6")
    freq = np.linspace(0.1, 5.0, 40)
    nodes = observation_nodes(cfg)
    study = Study("frf", cfg, (), samples=9, seed=5,
                  options={"model": "SM_CB2", "delta": None, "case": 4, "freq_hz": freq.tolist(), "nodes": nodes})
    ds = run_study(study, tmp_path / "frf", chunk=4, progress=False)
    assert ds["frf_db"].dims == ("sample", "point", "frequency") and ds["frf_db"].dtype == np.float32
    assert ds["frequency"].attrs["units"] == "Hz"
    env = envelope_from_samples(cfg, ds["frf_db"].values, ds["energy"].values, "SM_CB2", None, 4, seed=5,
                                freq_hz=freq, nodes=nodes, progress=False)
    ref = frf_envelope(cfg, "SM_CB2", None, 4, samples=9, seed=5, freq_hz=freq, progress=False)
    for name in ("nominal_db", "mean_db", "lower_db", "upper_db", "energy"):
        np.testing.assert_array_equal(getattr(env, name), getattr(ref, name), err_msg=name)
    c = with_overrides({**cfg, "craig_bampton": {"modes": [6, 3]}}, duration=20.0, transient=10.0, dt=1e-3)
    st = Study("structural", c, (8.0, 20.0), samples=5, seed=7,
               options={"model": "SM_CB2", "delta": 0.2, "case": None, "structural": True, "psd": None,
                        "eta_dt_s": 0.05})
    ds = run_study(st, tmp_path / "ss", chunk=2, progress=False, group="structure")
    ref = severity_study(c, [8.0, 20.0], 5, delta=0.2, seed=7, progress=False)
    np.testing.assert_array_equal(ds["severity"].values, ref.ss)
    np.testing.assert_array_equal(open_study(tmp_path / "ss", group="structure")["severity"].values, ref.ss)


def test_frf_and_robust_ss_commands_store_the_same_numbers(tmp_path, capsys):
    """frf --out stores every sample's FRF and prints the in-memory envelope; robust-ss --out stores one
    group per source of uncertainty and prints the in-memory result; both resume without recomputing."""
    import zarr
    from drillpy.cli import main
    frf = ["frf", "--preset", "thesis-ch6", "--model", "SM_CB2", "--case", "4", "--samples", "7", "--seed", "5",
           "--freqs", "0.1:5:30", "--json", "--no-progress"]
    assert main(frf) == 0
    plain = capsys.readouterr().out
    assert main([*frf, "--out", str(tmp_path / "frf"), "--chunk", "3"]) == 0
    assert capsys.readouterr().out == plain
    assert open_study(tmp_path / "frf")["frf_db"].shape == (7, 3, 30)
    rss = ["robust-ss", "--preset", "thesis-ch6", "--cb-modes", "6,3", "--dt", "1e-3", "--duration", "20",
           "--transient", "10", "--samples", "3", "--speeds", "8,20", "--seed", "7", "--delta", "0.2", "--json",
           "--no-progress"]
    assert main(rss) == 0
    plain = capsys.readouterr().out
    for _ in range(2):  # the second run finds every block done
        assert main([*rss, "--out", str(tmp_path / "rss"), "--chunk", "2"]) == 0
        assert capsys.readouterr().out == plain
    groups = set(zarr.open_group(str(tmp_path / "rss" / "study.zarr")).group_keys())
    assert groups == {"deterministic", "structure_SM_CB2"}
    assert open_study(tmp_path / "rss", group="structure_SM_CB2")["done"].values.all()


def test_a_cluster_that_loses_its_workers_is_one_error_not_a_hang():
    """A study's or a calibration's results awaited on a cluster with no worker left: a RuntimeError
    naming the scheduler after ``workerless_s``, not a wait without end."""
    pytest.importorskip("dask.distributed")
    import time
    from dask.distributed import Client, LocalCluster
    from drillpy.study.cluster import completed
    with LocalCluster(n_workers=1, threads_per_worker=1, processes=False, dashboard_address=":0") as cl, \
            Client(cl) as client:
        done = list(completed(client, [client.submit(abs, -k, pure=False) for k in range(5)]))
        assert sorted(f.result() for f in done) == [0, 1, 2, 3, 4]  # every future once
        futures = [client.submit(time.sleep, 6.0, pure=False)]
        cl.scale(0)
        start = time.perf_counter()
        with pytest.raises(RuntimeError, match=r"scheduler .*: no Dask worker for 2 s while 1 result"):
            list(completed(client, futures, workerless_s=2.0))
        assert time.perf_counter() - start < 30.0

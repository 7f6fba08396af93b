"""Chunks of a Monte Carlo study run apart merge into the study run at once, bit for bit
(``mc_samples.json``, :func:`drillpy.uncertainty.montecarlo.merge_studies`, ``drillpy mc-merge``; issue 13)."""
import json

import numpy as np
import pytest

from drillpy.cli import main
from drillpy.model.config import load_config, with_overrides
from drillpy.reports.stochastic import merge_outputs, read_samples, write_samples
from drillpy.uncertainty.montecarlo import merge_studies, stochastic_study

SHORT = dict(warmup=20.0, duration=30.0, transient=10.0)
SPEEDS = [12.0, 18.0, 24.0]


@pytest.fixture(scope="module")
def cfg():
    return with_overrides(load_config(preset="thesis-field"), modes=8)


def _study(cfg, n, first=0, seed=4):
    return stochastic_study(cfg, SPEEDS, n, seed, first_sample=first, threads=2, progress=False, **SHORT)


def test_chunks_written_and_merged_equal_the_study_run_at_once(cfg, tmp_path):
    whole = _study(cfg, 9)
    for first, n in ((0, 4), (4, 5)):
        write_samples(_study(cfg, n, first), tmp_path / f"chunk{first}")
    # any order of the chunks, through the files
    merged = merge_outputs([tmp_path / "chunk4", tmp_path / "chunk0" / "mc_samples.json"], tmp_path / "merged")
    np.testing.assert_array_equal(merged.severity, whole.severity)
    for name in ("mean", "q05", "q95", "p_exceed", "conv1", "deterministic"):
        np.testing.assert_array_equal(getattr(merged, name), getattr(whole, name), err_msg=name)
    assert merged.summary() == whole.summary()
    # the file round trip alone is exact too, and the merged folder holds the outputs
    assert read_samples(tmp_path / "merged").summary() == whole.summary()
    assert {p.name for p in (tmp_path / "merged").iterdir()} == {"mc.json", "mc_samples.json",
                                                                 "severity_band.png", "conv1.png"}
    js = json.loads((tmp_path / "merged" / "mc.json").read_text())
    assert js["samples"] == 9 and len(js["provenance"]["chunks"]) == 2


def test_chunks_that_do_not_tile_one_study_are_refused(cfg):
    a, b = _study(cfg, 3), _study(cfg, 3, first=4)
    with pytest.raises(ValueError, match=r"first_sample = 4: samples 3-3 gap between chunks"):
        merge_studies([a, b])
    with pytest.raises(ValueError, match=r"samples 2-2 overlap"):
        merge_studies([a, _study(cfg, 2, first=2)])
    with pytest.raises(ValueError, match=r"^seed: chunk starting at sample 3"):
        merge_studies([a, _study(cfg, 2, first=3, seed=5)])
    other = stochastic_study(cfg, SPEEDS, 2, 4, first_sample=3, threads=2, progress=False,
                             **{**SHORT, "duration": 31.0})
    with pytest.raises(ValueError, match=r"^(settings|config|deterministic): chunk starting at sample 3"):
        merge_studies([a, other])


def test_mc_merge_command(cfg, tmp_path, capsys):
    common = ["--preset", "thesis-field", "--modes", "8", "--speeds", "12,18,24", "--warmup", "20",
              "--duration", "30", "--transient", "10", "--seed", "4", "--no-progress"]
    assert main(["mc", *common, "--samples", "5", "--json"]) == 0
    whole = json.loads(capsys.readouterr().out)
    for first, n in ((0, 2), (2, 3)):
        assert main(["mc", *common, "--samples", str(n), "--first-sample", str(first), "--no-figures",
                     "--out", str(tmp_path / f"c{first}")]) == 0
        assert not list((tmp_path / f"c{first}").glob("*.png"))
    capsys.readouterr()
    assert main(["mc-merge", str(tmp_path / "c2"), str(tmp_path / "c0"), "--json"]) == 0
    merged = json.loads(capsys.readouterr().out)
    assert merged == whole
    assert main(["mc-merge", str(tmp_path / "c0"), str(tmp_path / "nowhere")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "nowhere" in err and "mc_samples.json" in err
    (tmp_path / "bad").mkdir()
    (tmp_path / "bad" / "mc_samples.json").write_text("[1, 2]")
    assert main(["mc-merge", str(tmp_path / "bad")]) == 2
    assert "not a samples file" in capsys.readouterr().err

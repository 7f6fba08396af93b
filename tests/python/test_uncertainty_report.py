"""drillpy.uncertainty_report: the chapter-6 conclusions measured on envelope widths, and the report."""
import json

import numpy as np
import pytest

import drillpy as d
from drillpy import frf as F
from drillpy.uncertainty_report import chapter6_report, conclusions, nominal_agreement

CFG = F.with_cb_modes(d.load_config(preset="thesis-ch6"), [10, 6])
FREQS = np.linspace(0.01, 10.0, 300)


@pytest.fixture(scope="module")
def envelopes():
    kw = dict(samples=150, freq_hz=FREQS, progress=False)
    models = {m: F.frf_envelope(CFG, m, 0.1, **kw) for m in F.MODELS}
    cases = {c: F.frf_envelope(CFG, "SM_CB2", case=c, **kw) for c in range(1, 8)}
    return models, cases


def test_conclusions_of_section_6_6(envelopes):
    rows = conclusions(*envelopes)
    assert len(rows) == 6
    by_claim = {r["claim"].split(" (")[0]: r for r in rows}
    damping = by_claim["damping uncertainty gives the thinnest envelopes"]
    # Damping fluctuations move the response by a fraction of a dB; mass and stiffness by several dB.
    assert max(damping["widths_db"]["case 2"]) < 1.0 < min(damping["widths_db"]["case 1"])
    for r in rows:
        assert r["holds"], r


def test_modal_rom_and_craig_bampton_nominal_frfs_agree():
    cfg = d.load_config(preset="thesis-ch6")
    f = np.linspace(0.05, 5.0, 200)
    assert nominal_agreement(cfg, f) < 3.0


def test_report_writes_every_figure(tmp_path):
    s = chapter6_report(CFG, tmp_path, samples=20, mode_samples=5, modes=(2, 4), freq_hz=FREQS, progress=False)
    pngs = sorted(p.name for p in tmp_path.glob("*.png"))
    assert len(pngs) == 3 + 9 + 1 + 2 + 1  # Figs. 6.1-6.12, C.2-C.4, CB convergence
    assert "figC_4_conv2_modes_BHA.png" in pngs
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert len(summary["conclusions"]) == 6 and summary["samples"] == 20
    assert summary["conv2_modes"]["modes"] == [2, 4]
    assert s["cb_convergence"]["max_rel_error_first5"][-1] < 1e-5

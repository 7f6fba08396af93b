"""The law evidence's effect size on the validation truths: the RMSE of the law residual of the
calibration part before and after each law-level effect is fitted on it alone
(:func:`drillpy.loop.evidence.law_evidence`), on records with and without that effect; the 10 %
threshold (``LAW_EFFECT_SIZE``) sits between them.

    PYTHONPATH=python python3 benchmarks/loop_law_evidence.py
"""
from __future__ import annotations

from loop_validation import DURATION_S, LOOP_DT_S, RATE_HZ

from drillpy import loop as L
from drillpy.loop.effects import CATALOGUE, stripped
from drillpy.loop.evidence import law_evidence
from drillpy.loop.fitting import fit_law
from drillpy.loop.run import analysis_config
from drillpy.loop.synthetic import declared_config, synthetic_record

#: (injected effects, seed): cases of benchmarks/loop_validation.py
CASES = [({}, 1), ({"string_stiffness": {}}, 41), ({"bit_hysteresis": {"beta1": 0.1}}, 21),
         ({"sensor_lag": {}, "bit_hysteresis": {}}, 32), ({"wob_coupling": {}}, 12)]


def main() -> None:
    opt = L.LoopOptions(rate_hz=RATE_HZ, dt_s=LOOP_DT_S)
    cfg = analysis_config(declared_config(), 1 / RATE_HZ, LOOP_DT_S)
    base = stripped(cfg)
    for eff, seed in CASES:
        data = L.prepare(synthetic_record(eff, duration_s=DURATION_S, seed=seed, fs_hz=RATE_HZ), cfg, opt)
        m = fit_law(L.LoopModel(base, dict(base["law"]), 8.5, 557.1), data)
        for name in ("bit_hysteresis", "wob_coupling"):
            before, after, why = law_evidence(CATALOGUE[name], m, data, opt)
            print(f"truth {'+'.join(eff) or 'none':<30} seed {seed}: {name:<15} law residual {before:.4f} -> "
                  f"{after:.4f} N m ({100 * (1 - after / before):5.1f} % lower){'' if why else '  credited'}")


if __name__ == "__main__":
    main()

"""`drillpy loop` on the independent whole-rig truth (benchmarks/whole_rig.py: motor with inertia,
jack, platform, exponential Stribeck law with ageing, quantized encoders, noise and glitches; no
drillpy code), as a user runs it on sample 175: from the ideal-drive ``thesis-rig`` declared model.

    PYTHONPATH=python python3 benchmarks/loop_whole_rig.py [--seed 5] [--duration 40] [--rate 1000] [--long-run-fluctuation record]

Prints the WOB-response test, every step with its validation error before and after, the final
effects and their parameters next to the truth's (jack: the product g tau, the steady WOB per rad/s
of speed deficit; motor: c_m 0.22 N m s/rad, J_m 0.013 kg m^2). Several minutes on the 2-core machine.
"""
from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seed", type=int, default=5)
    ap.add_argument("--duration", type=float, default=40.0)
    ap.add_argument("--rate", type=float, default=1000.0)
    ap.add_argument("--long-run-fluctuation", choices=("none", "record"), default="none",
                    help="the long runs' bit-rock torque (LoopOptions.long_run_fluctuation)")
    a = ap.parse_args(argv)
    import whole_rig
    from drillpy.loop import LoopOptions, run_loop
    from drillpy.model.config import load_config
    from drillpy.records.io import read_record
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "truth.mat"
        whole_rig.write_mat(whole_rig.simulate({"jack_steps": []}, duration=a.duration, seed=a.seed), str(path))
        rec = read_record(path)
    res = run_loop(rec, load_config(preset="thesis-rig"), LoopOptions(rate_hz=a.rate, long_run_fluctuation=a.long_run_fluctuation), log=lambda s: None)
    w = res.data.wob_response
    print(f"whole-rig truth, seed {a.seed}, {a.duration:g} s at {a.rate:g} Hz, long runs' torque fluctuation: "
          f"{a.long_run_fluctuation}")
    print(f"WOB: correlation {w['correlation']:.2f} at {1e3 * w['lag_s']:+.0f} ms, {w['gain_n_rad']:.0f} N/rad -> the law "
          f"takes the {w['input']}")
    print(f"baseline E {res.baseline.E_test:.4f} (damping {[round(z, 3) for z in res.baseline.model.damping_ratios]})")
    for s in res.steps:
        print(f"  {s.action:<7} {s.effect:<20} E {s.error_before:.4f} -> {s.error_after:.4f}")
    print(f"final E {res.final.E_test:.4f}, effects {list(res.final.model.effects)}, damping "
          f"{[round(z, 3) for z in res.final.model.damping_ratios]}")
    for name, p in res.final.model.effects.items():
        print(f"  {name}: " + ", ".join(f"{k} {v:.4g}" for k, v in p.items() if isinstance(v, float)))
        if name == "axial_jack":
            print(f"    g tau = {p['gain_n_rad'] * p['relaxation_s']:.1f} N s/rad")
    for k, r in enumerate(res.rounds, 1):
        for c in r:
            gain = c.get("relative_gain")
            pars = {n: v.get("value") for n, v in (c.get("parameters") or {}).items() if isinstance(v, dict)}
            print(f"  round {k}: {c['effect']:<20} gain {100 * gain:+5.1f} %" if gain is not None else
                  f"  round {k}: {c['effect']:<20} (no fit)", "accepted" if c["accepted"] else
                  "refused: " + "; ".join(c["reasons"])[:150],
                  ", ".join(f"{n} {v:.3g}" for n, v in pars.items() if isinstance(v, float)))
    for n in res.notes:
        print("  note:", n[:160])
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

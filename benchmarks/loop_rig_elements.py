"""Why the loop's one-mode model loses its cycle with the motor on sample 175, and what keeps it (issue 28).

    PYTHONPATH=python python3 benchmarks/loop_rig_elements.py [--record FILE.mat] [--keep DIR]

Runs ``drillpy analyze --calibrate 0:20`` (the rig modelled whole, one calibration of the long-run
metrics and the short-horizon E) and ``drillpy loop --preset thesis-rig --rate 250`` on the record,
then puts the whole-rig model's elements, at its calibrated values (the motor with its rotor and
shaft coupling, the jack, the damping ratio), into the loop's one-mode model, first with the loop's
own law (fitted on the short horizons) and then with the law ``analyze`` identified from the cycles
(Eq. 5.1 with its static torque, the torque scaled by the WOB), and prints for each model the
short-horizon E on the loop's calibration and validation parts and its long run (SS, stick fraction,
cycle frequency) against the record's. It also prints both laws at a few bit speeds. About 3 min.
docs/loop.md ("Test-rig sample 175") quotes it.
"""
from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
#: Bit speeds [rad/s] at which both laws are printed.
SPEEDS = (0.5, 1.0, 2.0, 4.0, 8.0, 12.0, 18.0)


def drillpy(*args: str) -> None:
    env = {**os.environ, "PYTHONPATH": str(REPO / "python")} if any((REPO / "python" / "drillpy").glob("_core*.so")) \
        else dict(os.environ)
    subprocess.run([sys.executable, "-m", "drillpy", *args], check=True, env=env, stdout=subprocess.DEVNULL)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--record", default=str(SAMPLE175))
    ap.add_argument("--keep", default=None, help="write the analysis and the loop into DIR (kept)")
    a = ap.parse_args()
    import numpy as np
    from drillpy import loop
    from drillpy.loop.longrun import long_run
    from drillpy.loop.run import analysis_config
    from drillpy.records import identification as ident
    from drillpy.loop.prediction import load_model
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(a.keep or tmp)
        drillpy("analyze", a.record, "--calibrate", "0:20", "--out", str(out / "analyze"))
        drillpy("loop", a.record, "--preset", "thesis-rig", "--rate", "250", "--out", str(out / "loop"))
        rig = load_model(out / "analyze" / "model.json")
        base = loop.LoopModel.from_dict(json.loads((out / "loop" / "model.json").read_text()))
        step = json.loads((out / "loop" / "loop.json").read_text())["time_step"]["used_s"]
    ct = base.channel_timing
    opt = loop.LoopOptions(rate_hz=250, channel_timing="none" if ct is None else (ct["top_lead_s"], ct["torque_lag_s"]))
    data = loop.prepare(a.record, base.engine_config(), opt, scale=base.metric_scale)
    base.cfg = analysis_config(base.cfg, data.dt, step)
    motor = {"variant": "motor", "droop_rad_s_per_nm": 1.0 / rig.motor_slope_nms_rad,
             "inertia_kg_m2": rig.motor_inertia_kg_m2, "command_rad_s": rig.command_rad_s,
             "coupling_stiffness_nm_rad": rig.coupling_stiffness_nm_rad}
    jack = {"gain_n_rad": rig.jack_gain_n_rad, "relaxation_s": rig.jack_relaxation_s}
    print(f"whole-rig model (drillpy analyze --calibrate 0:20): damping {rig.damping_ratio:.3f}, c_m "
          f"{rig.motor_slope_nms_rad:.3f} N m s/rad, J_m {rig.motor_inertia_kg_m2:.4f} kg m^2, command "
          f"{rig.command_rad_s:.2f} rad/s, coupling {rig.coupling_stiffness_nm_rad:.1f} N m/rad, jack "
          f"{rig.jack_gain_n_rad:.0f} N/rad, {rig.jack_relaxation_s:.3f} s")
    print(f"loop baseline (drillpy loop --rate 250): damping {base.damping_ratios}, effects {list(base.effects)}")
    for name, law in (("loop's law (short horizons)", base.law), ("analyze's law (the cycles)", rig.engine_law)):
        shape = {k: v for k, v in law.items() if k not in ("beta1", "beta2")}
        shape["type"] = "polynomial"
        T = ident.law_eval(shape, np.array(SPEEDS), 0.0, shape["wob_ref_n"])[0]
        print(f"  {name:30s} T [N m] at {', '.join(f'{v:g}' for v in SPEEDS)} rad/s: "
              + " ".join(f"{x:.3f}" for x in T))

    def model(law, zeta, effects):
        m = base.copy()
        m.cfg = {**m.cfg, "damping": {**m.cfg["damping"], "ratios": [zeta]}}
        m.law = dict(law)
        m.effects = effects
        return m

    z, own = rig.damping_ratio, dict(base.effects)
    rows = [("loop baseline", model(base.law, base.damping_ratios[0], own)),
            ("loop's law, the rig's damping", model(base.law, z, own)),
            ("  + motor", model(base.law, z, {**own, "top_drive_dynamics": motor})),
            ("  + motor + jack", model(base.law, z, {**own, "top_drive_dynamics": motor, "axial_jack": jack})),
            ("analyze's law, the rig's damping", model(rig.engine_law, z, {})),
            ("  + motor", model(rig.engine_law, z, {"top_drive_dynamics": motor})),
            ("  + motor + jack", model(rig.engine_law, z, {"top_drive_dynamics": motor, "axial_jack": jack}))]
    print(f"\n{'model':34s} {'E cal':>6s} {'E val':>6s}   long run: SS / stick fraction / cycle frequency")
    for label, m in rows:
        ev = loop.evaluate(m, data, 0)
        lr = long_run(m, data)
        if "error" in lr:
            print(f"{label:34s} {ev.E_train:6.3f} {ev.E_test:6.3f}   {lr['error']}")
            continue
        s = lr["model"]
        f = "none" if s["cycle_frequency_hz"] is None else f"{s['cycle_frequency_hz']:.2f} Hz"
        print(f"{label:34s} {ev.E_train:6.3f} {ev.E_test:6.3f}   {s['ss']:.3f} / {s['stick_fraction']:.3f} / {f}")
    r = lr["measured"]
    print(f"{'record':34s} {'':6s} {'':6s}   {r['ss']:.3f} / {r['stick_fraction']:.3f} / {r['cycle_frequency_hz']:.2f} Hz")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

"""The motor on sample 175, fitted from the whole-rig model's values with the damping free (issue 28).

    PYTHONPATH=python python3 benchmarks/loop_motor_probe.py

The loop's baseline of sample 175 (``thesis-rig``, 1000 Hz, the stall's horizons set apart) is
calibrated with the damping held by the limit cycle (0.133); the motor candidate then fits to a
quasi-static droop. This probe asks whether that is the start's doing: it starts the motor at the
whole-rig model's calibrated values (``drillpy analyze``: J_m 0.019 kg m^2, coupling 45 N m/rad,
c_m 0.25 N m s/rad, command 17.5 rad/s, damping 0.03), fits the law, the motor and (second row) the
damping ratio jointly on the calibration part's short horizons, and prints each fit's E on both parts,
its parameters and its long run (SS, stick fraction) against the record's. Two more rows ask whether
the record's break-away torque keeps the quasi-static motor sticking: the loop's motor candidate with
``static_friction`` held at the stick phases' 2.98 N m, and two with the jack (the WOB a state of the
model, ``axial_jack``) fitted beside it, the pair the whole-rig model has. Each fitted model is also run from rest (the
bit stuck, as the rig starts) for 40 s: a stick-slip cycle beside a stable sliding state would show
there. docs/loop.md quotes it. About 12 min on two cores.
"""
from __future__ import annotations

import sys
import warnings
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
    sys.path.insert(0, str(REPO / "python"))
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
WHOLE_RIG = {"variant": "motor", "droop_rad_s_per_nm": 4.0, "inertia_kg_m2": 0.019, "command_rad_s": 17.5,
             "coupling_stiffness_nm_rad": 45.0}
#: The loop's motor candidate on sample 175 (evidence.json): a droop without inertia, rigidly coupled.
QUASI_STATIC = {"variant": "motor", "droop_rad_s_per_nm": 1.76, "inertia_kg_m2": 1e-6, "command_rad_s": 12.38}
#: The record's break-away torque (the static_friction candidate's direct measurement), held.
STATIC = {"static_friction": {"static_torque_nm": 2.98, "source": "stick phases"}}
#: The jack from the whole-rig model's values (docs/records.md: 182-192 N/rad, 0.07-0.10 s).
JACK = {"axial_jack": {"gain_n_rad": 180.0, "relaxation_s": 0.1}}


def main() -> int:
    import drillpy
    from drillpy.loop import LoopOptions, run_loop
    from drillpy.loop.fitting import _calibrate, _finish
    from drillpy.loop.longrun import long_run
    from drillpy.loop.model import evaluate
    from drillpy.model.plausibility import fitted_values
    from drillpy.model.simulation import simulate
    warnings.simplefilter("ignore", UserWarning)
    res = run_loop(str(SAMPLE175), drillpy.load_config(preset="thesis-rig"), LoopOptions(max_steps=0),
                   log=lambda *a: None)
    data, base = res.data, res.baseline.model
    print(f"baseline: E_cal {res.baseline.E_train:.4f}, E_val {res.baseline.E_test:.4f}, damping "
          f"{base.damping_ratios[0]:.4f} (held)")
    # rows: the motor from the whole-rig values (damping held at 0.03 / fitted); the loop's quasi-static
    # droop with the record's break-away torque (static_friction at its stick phases' value; damping held
    # at the baseline's / fitted)
    rows = [("motor from the whole-rig values", WHOLE_RIG, None, 0.03, held) for held in (True, False)]
    rows += [("quasi-static motor and static_friction 2.98 N m", QUASI_STATIC, STATIC, None, held) for held in (True, False)]
    # the pair the whole-rig model has: the motor and the jack (the WOB as a state), fitted jointly
    rows += [("quasi-static motor and axial_jack", QUASI_STATIC, JACK, None, held) for held in (True, False)]
    for label, motor, extra, zeta, held in rows:
        m = base.copy()
        if zeta is not None:
            m.cfg["damping"]["ratios"] = [zeta]
        m.damping_held = held
        m.effects["top_drive_dynamics"] = dict(motor)
        if extra is not None:
            m.effects.update({k: dict(v) for k, v in extra.items()})
        with fitted_values():
            fit, _ = _calibrate(m, data, LoopOptions())
            fit = _finish(fit, data)
            ev, lr = evaluate(fit, data), long_run(fit, data)
        p = fit.effects["top_drive_dynamics"]
        jack = fit.effects.get("axial_jack")
        if jack:
            label += f" (gain {jack['gain_n_rad']:.4g} N/rad, relaxation {jack['relaxation_s']:.3g} s)"
        print(f"{label}, damping {'held' if held else 'fitted'}: E_cal {ev.E_train:.4f}, "
              f"E_val {ev.E_test:.4f}; damping {fit.damping_ratios[0]:.4f}, droop {p['droop_rad_s_per_nm']:.3g} rad/s "
              f"per N m, inertia {p['inertia_kg_m2']:.3g} kg m^2, command {p['command_rad_s']:.4g} rad/s, coupling "
              f"{p.get('coupling_stiffness_nm_rad', float('inf')):.4g} N m/rad; long run SS {lr['model']['ss']:.3f}, stick fraction "
              f"{lr['model']['stick_fraction']:.3f} (record {lr['measured']['ss']:.3f}, "
              f"{lr['measured']['stick_fraction']:.3f})", flush=True)
        # the long run above starts turning (Eq. 2.10); the rig starts from rest, the bit stuck: a
        # stick-slip cycle that coexists with a stable sliding state would show from there
        cfg = fit.engine_config()
        cfg["simulation"].update(duration_s=40.0, transient_s=10.0, start="rest", dt_s=2e-4)
        with fitted_values():
            r = simulate(cfg)
        print(f"  the same model from rest, 40 s: SS {r.severity:.3f}, stick fraction {r.stick_fraction:.3f}", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

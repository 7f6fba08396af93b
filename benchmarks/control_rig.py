"""Issue 15, item 4: would a controller have removed the stick-slip of sample 175 (thesis-rig at the
record's operating point), and at what motor torque?

Runs the thesis-rig preset (sample 175: 8.47 rad/s, 557 N) with the ideal drive, the stiff PI and
the gains `drillpy control --preset thesis-rig` tuned (read from its control.json), for three drive
inertias (the rig motor's is not in the thesis: 0.01 kg m^2 was assumed in the tuning) and prints SS,
stick fraction, peak and mean motor torque against the rig motor's 8 N m (thesis section 5.1).

    PYTHONPATH=python python3 -m drillpy control --preset thesis-rig --drive-inertia 0.01 --torque-limit 8 \
        --warmup 20 --duration 20 --transient 5 --samples 8 --validation-samples 32 --grid 5 --refine 14 \
        --factor-range 0.01,1000 --out /tmp/runs/rig2
    PYTHONPATH=python python3 benchmarks/control_rig.py /tmp/runs/rig2/control.json
"""
import json
import sys

from drillpy.control.episode import run_episode
from drillpy.control.tuning import controlled_drive
from drillpy.model.config import load_config

LIMIT = 8.0  # N m: the rig's brushless motor (thesis section 5.1: 300 RPM, 8 N m)


def main(path: str) -> None:
    tuned = {c: t["gains"] for c, t in json.loads(open(path).read())["tunings"].items()}
    cfg = load_config(preset="thesis-rig")
    speed, t0 = cfg["operation"]["top_speed_rad_s"], cfg["simulation"]["transient_s"]
    print(f"thesis-rig at {speed:.3f} rad/s, {cfg['operation']['wob_n']:g} N; {cfg['simulation']['duration_s']:g} s runs, "
          f"metrics after {t0:g} s; motor limit {LIMIT:g} N m")
    print("| drive | J [kg m^2] | SS | stick fraction | peak motor torque [N m] | mean motor torque [N m] |")
    print("|---|---|---|---|---|---|")
    s = run_episode(cfg, "ideal", None, speed).summary(t0)
    print(f"| ideal | - | {s['ss']:.3f} | {s['stick_fraction']:.3f} | {s['peak_motor_torque_nm']:.3f} | "
          f"{s['mean_motor_torque_nm']:.3f} |")
    for inertia in (0.001, 0.01, 0.1):
        drives = {"stiff": controlled_drive("stiff", inertia, LIMIT)}
        drives.update({f"{c} tuned": controlled_drive(c, inertia, LIMIT, g) for c, g in tuned.items()})
        for label, d in drives.items():
            s = run_episode(cfg, label, d, speed).summary(t0)
            print(f"| {label} | {inertia:g} | {s['ss']:.3f} | {s['stick_fraction']:.3f} | "
                  f"{s['peak_motor_torque_nm']:.3f} | {s['mean_motor_torque_nm']:.3f} |")


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "/tmp/runs/rig2/control.json")

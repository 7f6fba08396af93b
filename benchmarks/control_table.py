"""SS of thesis-field at a few top speeds for the ideal drive and the controlled top drives (issue 15).

    PYTHONPATH=python DRILLSIM=build/ctl/drillsim python3 benchmarks/control_table.py

Runs `drillsim --job sweep` once per drive on the thesis-field preset shortened to 100 s runs (SS
over the last 50 s, 20 modes, WOB 245 kN, start from rest) and prints a Markdown table (docs/control.md).
The drives: ideal (the thesis), and a controlled drive of inertia J = 2000 kg m^2 (an assumed field
top drive) with the stiff (bandwidth 20 w_1), soft_speed and z_torque controllers at their default tuning.
"""
import json
import os
import subprocess
import sys
import tempfile

from drillpy._core import preset_json

SPEEDS = [10.0, 12.0, 14.0, 16.0]
INERTIA = 2000.0
DRIVES = {
    "ideal": None,
    "stiff": {"type": "stiff"},
    "soft_speed": {"type": "soft_speed"},
    "z_torque": {"type": "z_torque"},
}


def main() -> int:
    drillsim = os.environ.get("DRILLSIM", "build/dev/drillsim")
    base = json.loads(preset_json("thesis-field"))
    base["simulation"].update({"duration_s": 100.0, "transient_s": 50.0})
    base["sweep"] = {"top_speeds_rad_s": SPEEDS, "wobs_n": [245e3]}
    rows = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, ctl in DRIVES.items():
            cfg = dict(base)
            if ctl is not None:
                cfg["top_drive"] = {"type": "controlled", "inertia_kg_m2": INERTIA, "controller": ctl}
            path = os.path.join(tmp, name + ".json")
            with open(path, "w") as f:
                json.dump(cfg, f)
            out = os.path.join(tmp, name)
            subprocess.run([drillsim, "--config", path, "--job", "sweep", "--out", out, "--quiet", "--threads", "2"],
                           check=True, stdout=subprocess.DEVNULL)
            with open(os.path.join(out, "summary.json")) as f:
                rows[name] = json.load(f)["severity"]
    print("| top speed [rad/s] | " + " | ".join(DRIVES) + " |")
    print("|---" * (len(DRIVES) + 1) + "|")
    for k, speed in enumerate(SPEEDS):
        print(f"| {speed:g} | " + " | ".join(f"{rows[n][k]:.3f}" for n in DRIVES) + " |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

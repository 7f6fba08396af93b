"""The cases of issue 31 ("one answer per question, in the user's units, with honest intervals, and
outputs that survive") re-run, each with its expected outcome; prints a table and the counts.

    PYTHONPATH=python python3 benchmarks/one_answer_cases.py [--only WORD]

Outcomes:
  ok       what the case expects: the one answer, the clear error (exit 2, one line naming the field or
           option), the warning naming the field, the output that survived;
  silent   accepted without a word where a word is due (a wrong answer waiting to happen);
  unclear  an answer or a message, but not the expected one (two numbers for one quantity, an error
           that misses the field, an interval that is not one);
  crash    a traceback, a signal or a timeout.
The target is 0 silent, 0 unclear, 0 crash. About four minutes on two cores.
"""
from __future__ import annotations

import argparse
import json
import math
import os
import re
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path
from types import SimpleNamespace

REPO = Path(__file__).resolve().parents[1]
RECORD = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
TIMEOUT_S = 600
ENV = {**os.environ, "PYTHONPATH": str(REPO / "python")}
THRESHOLD_LINE = re.compile(r"SS > 0\.5 below (\d+\.\d\d) \+- (\d\.\d\d) rad/s \((\d+\.\d) \+- (\d\.\d) RPM, bisection\)")


def run(*argv, timeout=TIMEOUT_S, **kw) -> subprocess.CompletedProcess:
    """``python -m drillpy ARGV`` from this checkout (not an installed drillpy)."""
    return subprocess.run([sys.executable, "-m", "drillpy", *map(str, argv)], capture_output=True, text=True,
                          env=ENV, timeout=timeout, **kw)


def crashed(r) -> str | None:
    """Why a finished command counts as a crash (a traceback or a signal), else None."""
    if "Traceback" in r.stderr or r.returncode < 0:
        return f"exit {r.returncode}: {r.stderr.strip().splitlines()[-1] if r.stderr.strip() else ''}"
    return None


def clear_error(r, needle: str) -> tuple:
    """A refusal: exit 2 and one ``drillpy: error:`` line holding ``needle``."""
    if crashed(r):
        return "crash", crashed(r)
    if r.returncode == 0:
        return "silent", "accepted"
    err = [ln for ln in r.stderr.splitlines() if ln.startswith("drillpy: error:")]
    if r.returncode == 2 and len(err) == 1 and needle in err[0]:
        return "ok", err[0][:150]
    return "unclear", r.stderr.strip()[:150]


def warned(r, needle: str) -> tuple:
    """Accepted with a ``drillpy: warning:`` line holding ``needle``."""
    if crashed(r):
        return "crash", crashed(r)
    lines = [ln for ln in r.stderr.splitlines() if ln.startswith("drillpy: warning:") and needle in ln]
    if lines:
        return "ok", lines[0][:150]
    return ("silent", "no warning") if r.returncode == 0 else ("unclear", r.stderr.strip()[:150])


# ------------------------------------------------------------------------------------------ 1. one answer
def _threshold_line(r) -> str | None:
    return next((ln for ln in r.stdout.splitlines() if ln.startswith("SS > 0.5 below")), None)


def case_report_field(tmp):
    r = run("report", "--preset", "thesis-field", "--out", tmp / "field", "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    line = _threshold_line(r)
    if not line or not THRESHOLD_LINE.fullmatch(line):
        return "unclear", f"headline {line!r}"
    return ("unclear", line) if "thesis" in line else ("ok", line)


def case_report_ch4(tmp):
    r = run("report", "--preset", "thesis-ch4", "--out", tmp / "ch4", "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    line = _threshold_line(r) or ""
    m = THRESHOLD_LINE.match(line)
    if m and "(thesis Fig. 4.8: 16.0 rad/s)" in line and abs(float(m.group(1)) - 16.0) < 0.1:
        return "ok", line
    return "unclear", line


def case_sweep_is_the_report(tmp):
    r = run("sweep", "--preset", "thesis-field", "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    s = json.loads((tmp / "field" / "summary.json").read_text())["sweep"] if (tmp / "field").is_dir() else None
    line = _threshold_line(r)
    if s is None:
        return "unclear", "report case not run"
    same = line is not None and f"{s['threshold_rad_s']:.2f} +- {s['threshold_precision_rad_s']:.2f}" in line
    grid = [ln for ln in r.stdout.splitlines() if "crosses 0.5 falling" in ln]  # a second number for it
    return ("ok", line) if same and not grid else ("unclear", f"{line} / report {s['threshold_rad_s']}; {grid}")


def case_readme_headline(tmp):
    line = _threshold_line(run("sweep", "--preset", "thesis-field", "--no-progress"))
    readme = (REPO / "README.md").read_text()
    return ("ok", "README quotes the printed line") if line and f"`{line}`" in readme else ("unclear", str(line))


def case_analyze_one_measured_side(tmp):
    r = run("analyze", RECORD, "--out", tmp / "analyze", "--folds", "0", "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    text = r.stdout + r.stderr
    record = re.search(r"stick fraction (\d\.\d+) \(measured from", text)
    measured = set(re.findall(r"stick fraction \d\.\d+ \(measured (\d\.\d+)\)", text))
    if record and measured == {record.group(1)}:
        return "ok", f"one measured stick fraction {record.group(1)} in {text.count('(measured ')} places"
    return "unclear", f"record {record and record.group(1)}, comparisons {sorted(measured)}"


# ------------------------------------------------------------------------------------------ 2. intervals
def case_mc_grid_limit(tmp):
    r = run("mc", "--preset", "thesis-field", "--samples", "20", "--speeds", "6:27:22", "--seed", "1",
                "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    zero = re.search(r"(\d+\.\d\d)-(\d+\.\d\d)", r.stdout)
    text = r.stdout + r.stderr
    if "grid" in text and "precision" in text:
        return "ok", next(ln for ln in text.splitlines() if "grid" in ln and "precision" in ln)[:150]
    return ("silent" if zero and zero.group(1) == zero.group(2) else "unclear"), r.stdout.splitlines()[-1][:150]


def case_control_binomial(tmp):
    r = run("control", "--preset", "thesis-field", "--drive-inertia", "2000", "--torque-limit", "50kNm",
                "--speeds", "14,20", "--wob", "245kN", "--samples", "2", "--validation-samples", "9", "--grid", "2",
                "--refine", "0", "--bootstrap", "20", "--warmup", "30", "--duration", "20", "--transient", "5",
                "--controllers", "z_torque", "--out", tmp / "control", "--no-progress")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    rows = re.findall(r"P\(SS > 0\.5 or stalled\) = (\d\.\d+) \[(\d\.\d+), (\d\.\d+)\]", r.stdout)
    bad = [x for x in rows if float(x[1]) == float(x[2])]
    if rows and not bad and "Wilson" in r.stdout + (tmp / "control" / "report.md").read_text():
        return "ok", "; ".join(f"{p} [{lo}, {hi}]" for p, lo, hi in rows)
    return "unclear", f"{rows}"


def case_control_one_threshold(tmp):
    """control's deterministic threshold is sweep's bisection (same configuration, drive and WOB), printed
    with its +- and RPM; no grid interpolation left."""
    if not (tmp / "control" / "control.json").is_file():
        case_control_binomial(tmp)
    comp = json.loads((tmp / "control" / "control.json").read_text())["comparison"]
    report = (tmp / "control" / "report.md").read_text()
    if "grid value" in report or any("deterministic_threshold_grid_rad_s" in r for r in comp.values()):
        return "unclear", "a grid value is still reported"
    found = []
    for label, extra in (("ideal", []), ("stiff", ["--controller", "stiff", "--drive-inertia", "2000",
                                                    "--torque-limit", "50kNm"])):
        r = run("sweep", "--preset", "thesis-field", "--speeds", "14,20", "--wob", "245kN", "--json", "--no-progress",
                *extra)
        if crashed(r) or r.returncode:
            return "crash", crashed(r) or r.stderr[-150:]
        sw, ctl = json.loads(r.stdout), comp[label]["deterministic_threshold"]
        if sw["threshold_rad_s"] is None or ctl["threshold_rad_s"] is None:
            return "unclear", f"{label}: sweep {sw['threshold_rad_s']}, control {ctl['threshold_rad_s']}"
        if abs(sw["threshold_rad_s"] - ctl["threshold_rad_s"]) > (sw["threshold_precision_rad_s"]
                                                                 + ctl["threshold_precision_rad_s"]):
            return "unclear", f"{label}: sweep {sw['threshold_rad_s']:.3f}, control {ctl['threshold_rad_s']:.3f}"
        text = (f"{ctl['threshold_rad_s']:.2f} +- {ctl['threshold_precision_rad_s']:.2f} "
                f"({ctl['threshold_rpm']:.1f} +- {ctl['threshold_precision_rpm']:.1f} RPM)")
        if text not in report:
            return "unclear", f"{label}: {text!r} not in report.md"
        found.append(f"{label} {ctl['threshold_rad_s']:.2f} (sweep {sw['threshold_rad_s']:.2f})")
    return "ok", "; ".join(found) + " rad/s, +- and RPM in report.md"


# ------------------------------------------------------------------------------------------ 3. units
def case_field_units_in_figures(tmp):
    r = run("simulate", "--preset", "thesis-rig", "--duration", "2", "--transient", "1", "--out", tmp / "field_fig",
            "--figure-units", "field")
    if crashed(r) or r.returncode:
        return "crash", crashed(r) or r.stderr[-150:]
    from drillpy.figures.simulation import severity_plot, stability_map_plot, time_series_plot
    import numpy as np
    t = np.linspace(0.0, 1.0, 3)
    labels = [severity_plot(None, [10.0, 20.0], [1.0, 0.1], units="field").axes[0].get_xlabel(),
              *(ax.get_ylabel() for ax in time_series_plot(None, t, t, 1e4 * t, units="field").axes),
              stability_map_plot(None, [60.0, 90.0], [200.0, 250.0], {"m": np.ones((2, 2))},
                                 units="field").axes[0].get_ylabel()]
    want = ["top-drive speed [RPM]", "speed [RPM]", "torque on bit [kft-lbf]", "weight on bit [klbf]"]
    return ("ok", "; ".join(labels)) if labels == want else ("unclear", str(labels))


#: the commands that write figures with speeds, WOB or torques on their axes
FIGURE_COMMANDS = ("report", "simulate", "sweep", "map", "mc", "mc-merge", "robust-ss", "control", "analyze",
                   "predict", "loop")


def case_figure_units_on_every_command(tmp):
    """Every figure-writing command takes --figure-units; the plots of report/mc/control/robust-ss/analyze
    label their axes in field units when asked, SI by default."""
    missing = []
    for cmd in FIGURE_COMMANDS:
        r = run(cmd, "--help")
        if crashed(r) or r.returncode:
            return "crash", crashed(r) or r.stderr[-150:]
        if "--figure-units" not in r.stdout:
            missing.append(cmd)
    if missing:
        return "silent", f"no --figure-units on {', '.join(missing)}"
    import numpy as np

    from drillpy.figures import control, frf, records, stochastic
    sp = np.array([10.0, 20.0])
    st = SimpleNamespace(speeds=sp, q05=sp * 0, q95=sp * 0 + 1, mean=sp * 0 + 0.5, severity=np.ones((2, 2)),
                         deterministic=None, p_exceed=sp * 0, p05_speed=None, deterministic_threshold=15.0)
    ctl = SimpleNamespace(comparison={"ideal": {"map": np.array([[1.2, 0.1], [1.3, 0.2]])}},
                          validation_window=SimpleNamespace(speeds=sp, wobs=np.array([200e3, 245e3])))
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_mat
    raw = read_mat(RECORD)
    rec, rep = clean(raw)

    def draw(units):
        return [stochastic.severity_band_plot(None, st, units=units).axes[1].get_xlabel(),
                frf.severity_bands_plot(None, sp, {"d": SimpleNamespace(ss=np.ones((1, 2)))}, units=units
                                        ).axes[1].get_xlabel(),
                *(control.maps_plot(None, ctl, units).axes[0].get_xlabel(),
                  control.maps_plot(None, ctl, units).axes[0].get_ylabel()),
                records.record_time_series_plot(None, raw, rec, rep, units=units).axes[1].get_ylabel()]
    field, si = draw("field"), draw("si")
    want = ["top-drive speed [RPM]", "top-drive speed [RPM]", "top speed [RPM]", "WOB [klbf]",
            "torque on bit [ft-lbf]"]
    want_si = ["top-drive speed [rad/s]", "top-drive speed [rad/s]", "top speed [rad/s]", "WOB [kN]",
               "torque on bit [N m]"]
    if field == want and si == want_si:
        return "ok", f"{len(FIGURE_COMMANDS)} commands take it; " + "; ".join(field)
    return "unclear", f"field {field}; si {si}"


def case_speed_unit_renamed(tmp):
    return clear_error(run("simulate", "--preset", "thesis-field", "--top-speed", "160", "--speed-unit", "rpm"),
                       "--law-speed-unit")


def case_units_are_si(tmp):
    a = run("simulate", "--preset", "thesis-field", "--top-speed", "160rpm", "--wob", "45klbf", "--json")
    b = run("simulate", "--preset", "thesis-field", "--top-speed", repr(160 * math.pi / 30), "--wob",
                repr(45e3 * 4.4482216152605), "--json")
    if crashed(a) or a.returncode or b.returncode:
        return "crash", crashed(a) or a.stderr[-150:]
    return ("ok", "160rpm / 45klbf = the SI run") if a.stdout == b.stdout else ("unclear", "runs differ")


def case_wob_everywhere(tmp):
    out = []
    for argv in (["sweep", "--speeds", "150,200rpm"], ["mc", "--samples", "2", "--speeds", "16", "--warmup", "0",
                                                          "--no-figures"]):
        runs = [run(*argv[:1], "--preset", "thesis-field", *argv[1:], "--wob", w, "--json", "--no-progress")
                for w in ("200kN", "245kN")]
        if any(crashed(r) or r.returncode for r in runs):
            return "crash", f"{argv[0]}: {runs[0].stderr[-120:]}"
        out.append(runs[0].stdout != runs[1].stdout)
    return ("ok", "sweep and mc follow --wob (control: the control case)") if all(out) else ("silent", str(out))


# ------------------------------------------------------------------------------------------ 4. outputs
def _done_blocks(out: Path) -> int:
    from drillpy.study.store import open_study
    try:
        return int(open_study(out)["done"].values.sum())
    except Exception:  # not there yet, or being written
        return 0


def case_ctrl_c_mc_new_dir(tmp):
    out = tmp / "new" / "mc"
    argv = ["mc", "--preset", "thesis-field", "--samples", "60", "--chunk", "10", "--speeds", "12,16,20,24",
            "--seed", "2", "--no-figures", "--json", "--no-progress"]
    p = subprocess.Popen([sys.executable, "-m", "drillpy", *argv, "--out", str(out)], env=ENV,
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while time.time() - t0 < 120 and _done_blocks(out) < 1:  # Ctrl-C once a block is stored
        time.sleep(0.5)
    p.send_signal(signal.SIGINT)
    _, err = p.communicate(timeout=120)
    if p.returncode != 130 or not (out / "study.zarr").is_dir():
        return "unclear", f"exit {p.returncode}, store kept: {(out / 'study.zarr').is_dir()}: {err[-120:]}"
    again = run(*argv, "--out", out)
    once = run(*argv, "--out", tmp / "once")
    if again.returncode or once.returncode:
        return "crash", again.stderr[-150:]
    same = json.loads(again.stdout)["speeds"] == json.loads(once.stdout)["speeds"]
    return ("ok", "finished blocks kept, the rerun resumed to the uninterrupted numbers") if same else \
        ("unclear", "resumed numbers differ")


def _two_writers(argv_a, argv_b, out):
    from drillpy.outputs import LOCK_NAME
    pa = subprocess.Popen([sys.executable, "-m", "drillpy", *map(str, argv_a), "--out", str(out)], env=ENV,
                          stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    t0 = time.time()
    while time.time() - t0 < 60 and not (out / LOCK_NAME).exists() and pa.poll() is None:
        time.sleep(0.05)  # the second writer starts while the first one writes
    b = run(*argv_b, "--out", out)
    _, err_a = pa.communicate(timeout=TIMEOUT_S)
    return pa.returncode, err_a, b


def case_two_simulates(tmp):
    out = tmp / "two_sim"
    ra, err_a, b = _two_writers(["simulate", "--preset", "thesis-field", "--top-speed", "16", "--duration", "3000",
                                 "--transient", "200"],
                                ["simulate", "--preset", "thesis-field", "--top-speed", "20"], out)
    if ra != 0:
        return "crash", err_a[-150:]
    verdict = clear_error(b, "another drillpy command")
    summary = json.loads((out / "summary.json").read_text())
    if verdict[0] == "ok" and summary["config"]["operation"]["top_speed_rad_s"] == 16.0:
        return verdict
    return "unclear", f"{verdict}; summary at {summary['config']['operation']['top_speed_rad_s']} rad/s"


def case_two_mcs(tmp):
    argv = ["mc", "--preset", "thesis-field", "--samples", "400", "--speeds", "12,16,20", "--no-figures",
            "--no-progress"]
    ra, err_a, b = _two_writers(argv, argv, tmp / "two_mc")
    if ra != 0:
        return "crash", err_a[-150:]
    return clear_error(b, "another drillpy command")


def case_empty_out(tmp):
    return clear_error(run("simulate", "--preset", "thesis-rig", "--out", ""), "--out = ''")


# ------------------------------------------------------------------------------------------ 5. figures
def case_loop_labels(tmp):
    from drillpy.figures.loop import errors_plot
    ev = SimpleNamespace(E_train=0.3, E_test=0.3)
    steps = [SimpleNamespace(action="add", effect="bit_hysteresis", after=ev),
             SimpleNamespace(action="remove", effect="bit_hysteresis", after=ev)]
    res = SimpleNamespace(baseline=ev, steps=steps, rounds=[])
    fig = errors_plot(tmp / "errors.png", res)
    labels = [t.get_text() for t in fig.axes[0].get_xticklabels()]
    ok = labels == ["baseline", "+ bit_hysteresis (added)", "- bit_hysteresis (removed)"]
    return ("ok" if ok else "unclear"), str(labels)


def case_control_map_one_wob(tmp):
    import numpy as np

    from drillpy.figures.control import maps_plot
    m = np.array([[1.2, 0.8, 0.3, 0.1]])
    study = SimpleNamespace(comparison={"ideal": {"map": m}, "z_torque": {"map": m / 4}},
                            validation_window=SimpleNamespace(speeds=np.array([8.0, 12.0, 16.0, 20.0]),
                                                              wobs=np.array([245e3])))
    fig = maps_plot(tmp / "maps.png", study)
    shown = [ax for ax in fig.axes if ax.get_visible() and ax.get_label() != "<colorbar>"]
    blank = [ax.get_title() for ax in shown if not ax.lines and not ax.collections]
    return ("ok", f"{len(shown)} panels, all drawn") if shown and not blank else ("unclear", f"blank: {blank}")


def case_plots_return_figures(tmp):
    import inspect

    import matplotlib.figure

    from drillpy.figures import control, frf, loop, records, simulation, stochastic
    fig = simulation.severity_plot(tmp / "s.png", [6.0, 7.0], [1.0, 0.2], 6.5)
    names = [f"{m.__name__}.{n}" for m in (control, frf, loop, records, simulation, stochastic)
             for n, f in inspect.getmembers(m, inspect.isfunction) if n.endswith("_plot") and f.__module__ == m.__name__
             and "-> Path" in inspect.getsource(f).split("\n")[0]]
    ok = isinstance(fig, matplotlib.figure.Figure) and not names
    return ("ok", "every *_plot returns its Figure") if ok else ("unclear", f"{type(fig).__name__}; {names[:4]}")


# ------------------------------------------------------------------------------------------ 6. plausibility
def _config_case(tmp, name, edit, needle):
    from drillpy.model.config import load_config
    c = load_config(preset="thesis-field")
    edit(c)
    path = tmp / f"{name}.json"
    path.write_text(json.dumps(c))
    return warned(run("simulate", "--config", path, "--duration", "20", "--transient", "10"), needle)


def _section(key, value):
    def edit(c):
        c["string"]["sections"][0][key] = value
    return edit


def case_radius(tmp):
    return _config_case(tmp, "radius", _section("outer_radius_m", 63.5), "outer_radius_m = 63.5")


def case_modulus(tmp):
    return _config_case(tmp, "modulus", _section("youngs_modulus_pa", 207.0), "youngs_modulus_pa = 207")


def case_length(tmp):
    return _config_case(tmp, "length", _section("length_m", 1e308), "length_m (total) = 1e+308")


def case_b0(tmp):
    def edit(c):
        c["law"]["b0"] = -3478.0
    return _config_case(tmp, "b0", edit, "law.b0 = -3478")


def case_rpm_as_rad_s(tmp):
    return warned(run("simulate", "--preset", "thesis-field", "--top-speed", "120", "--duration", "20",
                          "--transient", "10"), "it is 12.6 rad/s")


def case_density_blamed(tmp):
    return _config_case(tmp, "density", _section("density_kg_m3", 7.85), "density_kg_m3 = 7.85")


def case_api_negative_wob(tmp):
    import drillpy
    try:
        drillpy.simulate(drillpy.load_config(preset="thesis-field"), wob=-150e3, record=False)
    except ValueError as e:
        r = run("simulate", "--preset", "thesis-field", "--wob", "-150kN")
        return ("ok", str(e)) if r.stderr.strip() == f"drillpy: error: {e}" else ("unclear", f"{e} / {r.stderr}")
    return "silent", "accepted"


def case_threshold_nan(tmp):
    import drillpy
    try:
        v = drillpy.severity_threshold([10.0, 12.0, 14.0], [1.2, math.nan, 0.2])
    except ValueError as e:
        return ("ok", str(e)[:150]) if "severities[1] = nan" in str(e) else ("unclear", str(e))
    return "silent", f"answered {v}"


def case_pi_without_gains(tmp):
    r = run("simulate", "--preset", "thesis-field", "--controller", "pi", "--drive-inertia", "2000",
                "--duration", "20", "--transient", "10")
    if crashed(r):
        return "crash", crashed(r)
    return ("ok", r.stdout.strip()) if r.returncode == 0 else ("unclear", r.stderr.strip()[:150])


def case_analyze_without_stick(tmp):
    import numpy as np
    r = run("simulate", "--preset", "thesis-rig", "--top-speed", "20", "--duration", "40", "--transient", "5",
            "--out", tmp / "no_stick")
    if r.returncode:
        return "crash", r.stderr[-150:]
    d = np.loadtxt(tmp / "no_stick" / "series.csv", delimiter=",", comments="#", skiprows=2)
    rec = tmp / "no_stick.csv"  # an oscillating record whose bit never stops (SS 0.77, stick fraction 0)
    np.savetxt(rec, d[:, [0, 1, 6, 4]], delimiter=",", fmt="%.7g", comments="",
               header="time_s,bit_speed_rad_s,top_speed_rad_s,torque_on_bit_Nm")
    return warned(run("analyze", rec, "--no-sim", "--folds", "0", "--out", tmp / "no_stick_an", "--no-progress"),
                  "not stick-slip")


def case_deep_json(tmp):
    deep = tmp / "deep.json"
    deep.write_text("[" * 200_000 + "]" * 200_000)
    t0 = time.perf_counter()
    r = run("simulate", "--config", deep, timeout=120)
    took = time.perf_counter() - t0  # the interpreter's start included
    verdict = clear_error(r, f"config = '{deep}': JSON nested too deep: more than 64 levels")
    if len(r.stderr) >= 1000 or took > 5.0:
        return "unclear", f"{took:.1f} s, {len(r.stderr)}-byte message"
    return verdict


def case_tiny_dt(tmp):
    return clear_error(run("simulate", "--preset", "thesis-rig", "--dt", "1e-12"),
                       "simulation.dt_s = 1e-12 with simulation.duration_s = 40")


def drillsim_path() -> Path | None:
    """drillsim of this checkout's development build, else the one on PATH."""
    import shutil
    built = REPO / "build" / "dev" / "drillsim"
    found = str(built) if built.is_file() else shutil.which("drillsim")
    return Path(found) if found else None


def drillsim_error(argv, needle: str, *, within_s: float) -> tuple:
    """A drillsim refusal: exit 2, one short ``drillsim: error:`` line holding ``needle``, within ``within_s``."""
    exe = drillsim_path()
    if exe is None:
        return "crash", "drillsim not built (scripts/dev-build.sh)"
    t0 = time.perf_counter()
    r = subprocess.run([str(exe), *map(str, argv)], capture_output=True, text=True, timeout=TIMEOUT_S)
    took = time.perf_counter() - t0
    if r.returncode < 0:
        return "crash", f"signal {-r.returncode}"
    if r.returncode == 0:
        return "silent", "accepted"
    one = r.stderr.count("\n") == 1 and r.stderr.startswith("drillsim: error:") and len(r.stderr) < 300
    if r.returncode == 2 and one and needle in r.stderr and took < within_s:
        return "ok", f"{took:.2f} s: {r.stderr.strip()[:150]}"
    return "unclear", f"{took:.1f} s, exit {r.returncode}, {len(r.stderr)} bytes: {r.stderr.strip()[:120]}"


def case_drillsim_deep_json(tmp):
    deep = tmp / "deep_drillsim.json"
    deep.write_text("[" * 200_000 + "]" * 200_000)
    return drillsim_error(["--config", deep, "--out", tmp / "deep_out"],
                          f"--config {deep}: JSON nested too deep: more than 64 levels", within_s=1.0)


def case_drillsim_tiny_dt(tmp):
    import drillpy
    cfg = drillpy.load_config(preset="thesis-rig")
    cfg["simulation"]["dt_s"] = 1e-12
    (tmp / "tiny_dt.json").write_text(json.dumps(cfg))
    return drillsim_error(["--config", tmp / "tiny_dt.json", "--out", tmp / "tiny_dt_out"],
                          "simulation.dt_s = 1e-12 with simulation.duration_s = 40", within_s=5.0)


CASES = [
    ("report thesis-field: the bisection threshold with +- and RPM, no thesis value", case_report_field),
    ("report thesis-ch4: the threshold beside the thesis's 16 rad/s it reproduces", case_report_ch4),
    ("sweep prints the report's threshold, no second number for it", case_sweep_is_the_report),
    ("README headline is the printed line", case_readme_headline),
    ("analyze sample 175: one measured stick fraction everywhere", case_analyze_one_measured_side),
    ("mc: a grid-limited interval is said to be one", case_mc_grid_limit),
    ("control: P(SS > 0.5) with a binomial (Wilson) interval, never [p, p]", case_control_binomial),
    ("control: the deterministic threshold is sweep's bisection, with +- and RPM", case_control_one_threshold),
    ("--speed-unit: an error naming --law-speed-unit", case_speed_unit_renamed),
    ("--top-speed 160rpm --wob 45klbf: the SI run", case_units_are_si),
    ("--wob on sweep and mc", case_wob_everywhere),
    ("--figure-units field: RPM, klbf and kft-lbf on the axes", case_field_units_in_figures),
    ("--figure-units on every figure command, field units on their plots' axes", case_figure_units_on_every_command),
    ("Ctrl-C during mc --out NEWDIR: blocks kept, rerun resumes", case_ctrl_c_mc_new_dir),
    ("two simulates into one --out: one clear error, outputs of one run", case_two_simulates),
    ("two mcs into one --out: one clear error", case_two_mcs),
    ("--out '': an error", case_empty_out),
    ("loop errors_plot: a removed effect labelled removed", case_loop_labels),
    ("control map with one WOB: no blank panel", case_control_map_one_wob),
    ("every *_plot returns its matplotlib Figure", case_plots_return_figures),
    ("radius 63.5 m: a warning naming the field", case_radius),
    ("E = 207 Pa: a warning naming the field", case_modulus),
    ("a 1e308 m string: a warning", case_length),
    ("b0 = -3478: a warning", case_b0),
    ("120 rad/s typed for 120 RPM: a warning with the RPM reading", case_rpm_as_rad_s),
    ("density 7.85: the density is named, not the time step", case_density_blamed),
    ("drillpy.simulate(cfg, wob=-150e3): refused as the CLI refuses it", case_api_negative_wob),
    ("severity_threshold with NaN: an error naming it", case_threshold_nan),
    ("--controller pi without gains: runs with the promised tuning", case_pi_without_gains),
    ("analyze on a record without a stick phase: said to be no stick-slip", case_analyze_without_stick),
    ("a tiny dt: an error naming dt", case_tiny_dt),
    ("a 200 000-deep JSON array as --config: one short error naming the file, in under 5 s", case_deep_json),
    ("drillsim: a 200 000-deep JSON array: one short error naming the file, in under 1 s", case_drillsim_deep_json),
    ("drillsim: a tiny dt: an error naming dt_s with duration_s", case_drillsim_tiny_dt),
]


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--only", help="run the cases whose title contains WORD")
    a = ap.parse_args(argv)
    sys.path.insert(0, str(REPO / "python"))
    import matplotlib
    matplotlib.use("Agg")
    counts = {k: 0 for k in ("ok", "silent", "unclear", "crash")}
    with tempfile.TemporaryDirectory() as d:
        tmp = Path(d)
        print(f"{'#':>2}  {'outcome':8s} {'s':>5}  case: detail")
        for i, (title, fn) in enumerate(CASES, 1):
            if a.only and a.only.lower() not in title.lower():
                continue
            t0 = time.time()
            try:
                with warnings.catch_warnings():
                    warnings.simplefilter("ignore")
                    outcome, detail = fn(tmp)
            except subprocess.TimeoutExpired:
                outcome, detail = "crash", "timeout"
            except Exception as e:  # a crash of the case itself is a crash of what it runs
                outcome, detail = "crash", f"{type(e).__name__}: {e}"[:150]
            counts[outcome] += 1
            print(f"{i:2d}  {outcome:8s} {time.time() - t0:5.1f}  {title}: {detail}", flush=True)
    print(f"\n{counts['silent']} silent, {counts['unclear']} unclear, {counts['crash']} crash "
          f"({counts['ok']} ok of {sum(counts.values())})")
    return 0 if counts["silent"] == counts["unclear"] == counts["crash"] == 0 else 1


if __name__ == "__main__":
    sys.exit(main())

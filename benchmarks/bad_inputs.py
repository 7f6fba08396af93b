"""The bad-input catalogue (issue 13): every entry point fed inputs a user gets wrong, each outcome
classified, counts printed.

    PYTHONPATH=python DRILLSIM=build/dev/drillsim python3 benchmarks/bad_inputs.py [--list] [--only WORD]

Outcomes:
  clear    refused with exit status 2 (or a ValueError in Python) and ONE line naming the field or
           option and, where it has one, the value (the entry's ``needle``);
  flagged  accepted, with a warning line naming the problem (records that are readable but
           implausible: the run goes on, the warning is in the output);
  unclear  refused, but the message misses the needle or spans several lines;
  silent   accepted without a word (a wrong result waiting to happen);
  crash    a traceback, a signal, a hang (timeout) or NaN in a JSON output.
The first two are the wanted outcomes. The catalogue covers the 17 silent and 7 unclear inputs the
issue lists and the other ways in: configuration files (drillsim and drillpy), drillpy and
drillsim options, records, the Python API.
"""
from __future__ import annotations

import argparse
import copy
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parents[1]
RECORD = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"
TIMEOUT_S = 300


def _tree_env() -> dict:
    """The environment of a drillpy subprocess: the in-tree build when there is one, else the installed drillpy."""
    if any((REPO / "python" / "drillpy").glob("_core*.so")):
        return {**os.environ, "PYTHONPATH": str(REPO / "python")}
    return dict(os.environ)


def _drillsim() -> str:
    for c in (os.environ.get("DRILLSIM"), shutil.which("drillsim"), REPO / "build" / "dev" / "drillsim",
              REPO / "build" / "ctest" / "drillsim"):
        if c and Path(c).is_file():
            return str(c)
    sys.exit("drillsim not found: set DRILLSIM")


def _base_config() -> dict:
    from drillpy.model.config import load_config, with_overrides
    return with_overrides(load_config(preset="thesis-rig"), duration=4.0, transient=1.0)


def _edit(path: list, value):
    """A config edit setting ``path`` (keys and indices) to ``value``; the sentinel DELETE removes it."""
    def apply(c):
        node = c
        for k in path[:-1]:
            node = node[k]
        if value is DELETE:
            del node[path[-1]]
        else:
            node[path[-1]] = value
    return apply


DELETE = object()

#: (label, edit of the thesis-rig config, needle the error must contain)
CONFIG_EDITS = [
    ("elements wrap 2^32+20", _edit(["string", "sections", 0, "elements"], 4294967316), "4294967316"),
    ("modes wrap 2^32+1", _edit(["rom", "modes"], 4294967297), "rom.modes"),
    ("elements 1e12 (float)", _edit(["string", "sections", 0, "elements"], 1e12), "elements"),
    ("elements 2.5", _edit(["string", "sections", 0, "elements"], 2.5), "elements = 2.5"),
    ("elements -3", _edit(["string", "sections", 0, "elements"], -3), "elements = -3"),
    ("modes 0", _edit(["rom", "modes"], 0), "rom.modes = 0"),
    ("damping ratio 5", _edit(["damping", "ratios"], [5.0]), "damping.ratios[0] = 5"),
    ("damping ratio -0.1", _edit(["damping", "ratios"], [-0.1]), "damping.ratios[0] = -0.1"),
    ("damping ratio text", _edit(["damping", "ratios"], ["x"]), "damping.ratios[0]"),
    ("damping ratios empty", _edit(["damping", "ratios"], []), "damping.ratios"),
    ("damping type", _edit(["damping", "type"], "viscous"), "damping.type"),
    ("rayleigh pairs malformed", _edit(["damping"], {"type": "rayleigh", "pairs": [1, 2]}), "damping.pairs"),
    ("stick threshold 5", _edit(["metrics", "stick_threshold_fraction"], 5), "stick_threshold_fraction = 5"),
    ("stick threshold 0", _edit(["metrics", "stick_threshold_fraction"], 0), "stick_threshold_fraction = 0"),
    ("slip level 2", _edit(["metrics", "slip_level_fraction"], 2), "slip_level_fraction = 2"),
    ("debounce -1", _edit(["metrics", "stick_debounce_s"], -1), "stick_debounce_s = -1"),
    ("dt 0", _edit(["simulation", "dt_s"], 0), "dt_s = 0"),
    ("dt -1", _edit(["simulation", "dt_s"], -1), "dt_s = -1"),
    ("dt 0.5 (unstable)", _edit(["simulation", "dt_s"], 0.5), "dt_s = 0.5"),
    ("transient > duration", _edit(["simulation", "transient_s"], 10.0), "transient_s = 10"),
    ("output stride 0", _edit(["simulation", "output_stride"], 0), "output_stride = 0"),
    ("scheme unknown", _edit(["simulation", "scheme"], "rk4"), "scheme"),
    ("start unknown", _edit(["simulation", "start"], "sideways"), "sideways"),
    ("wob -3", _edit(["operation", "wob_n"], -3.0), "wob_n = -3"),
    ("top speed text", _edit(["operation", "top_speed_rad_s"], "fast"), "top_speed_rad_s"),
    ("bit viscous -1", _edit(["operation", "bit_viscous_nms"], -1.0), "bit_viscous_nms = -1"),
    ("unknown key", _edit(["colour"], "red"), "colour"),
    ("unknown key in law", _edit(["law", "b9"], 1.0), "law.b9"),
    ("law missing", _edit(["law"], DELETE), "law"),
    ("law type unknown", _edit(["law", "type"], "coulomb"), "coulomb"),
    ("speed unit unknown", _edit(["law", "speed_unit"], "mph"), "mph"),
    ("sections empty", _edit(["string", "sections"], []), "sections"),
    ("outer < inner radius", _edit(["string", "sections", 0, "inner_radius_m"], 1.0), "inner_radius_m = 1"),
    ("density 0", _edit(["string", "sections", 0, "density_kg_m3"], 0.0), "density_kg_m3 = 0"),
    ("youngs modulus -1", _edit(["string", "sections", 0, "youngs_modulus_pa"], -1.0), "youngs_modulus_pa = -1"),
    ("poisson 0.7", _edit(["string", "sections", 0, "poisson_ratio"], 0.7), "poisson_ratio = 0.7"),
    ("lumped node 999", _edit(["string", "lumped_inertias"], [{"node": 999, "inertia_kg_m2": 1.0}]), "999"),
    ("lumped inertia -1", _edit(["string", "lumped_inertias"], [{"node": -1, "inertia_kg_m2": -1.0}]),
     "inertia_kg_m2 = -1"),
    ("motor inertia 0", _edit(["top_drive"], {"type": "motor", "slope_nms_rad": 1.0, "inertia_kg_m2": 0.0}),
     "inertia_kg_m2 = 0"),
    ("top drive type", _edit(["top_drive"], {"type": "diesel"}), "diesel"),
    ("lowpass -5", _edit(["sensors"], {"lowpass_hz": -5.0}), "lowpass_hz = -5"),
    ("craig-bampton modes 0", _edit(["craig_bampton"], {"modes": [0, 3]}), "craig_bampton.modes[0] = 0"),
    ("sweep speed text", _edit(["sweep"], {"top_speeds_rad_s": ["a"]}), "top_speeds_rad_s[0]"),
]

#: (label, raw file text, needle) for files that are not a valid JSON configuration
CONFIG_TEXTS = [
    ("duplicate key", None, "duplicate key"),
    ("malformed JSON", '{"string": [1, 2', "malformed JSON"),
    ("empty file", "", "malformed JSON"),
    ("JSON array", "[1, 2]", "config"),
    ("NaN literal", None, ("malformed JSON", "wob_n = nan")),  # Python's json reads NaN
]


def _config_text_cases(base: dict) -> list:
    out = []
    for label, text, needle in CONFIG_TEXTS:
        if label == "duplicate key":
            t = json.dumps(base).replace('"rom": {', '"rom": {"modes": 3, ', 1)
        elif label == "NaN literal":
            t = json.dumps(base).replace('"wob_n": ', '"wob_n": NaN, "x": ', 1)
        else:
            t = text
        out.append((label, t, needle))
    return out


#: (label, drillpy argv, needle); quick runs only (a valid run would take seconds)
DRILLPY_ARGS = [
    ("simulate --top-speed -8", ["simulate", "--preset", "thesis-rig", "--top-speed", "-8"], "-8"),
    ("simulate --top-speed 0", ["simulate", "--preset", "thesis-rig", "--top-speed", "0"], "top"),
    ("simulate --top-speed abc", ["simulate", "--preset", "thesis-rig", "--top-speed", "abc"], "abc"),
    ("simulate --top-speed nan", ["simulate", "--preset", "thesis-rig", "--top-speed", "nan"], "nan"),
    ("simulate --top-speed inf", ["simulate", "--preset", "thesis-rig", "--top-speed", "inf"], "inf"),
    ("simulate --wob -3kN", ["simulate", "--preset", "thesis-rig", "--wob", "-3kN"], "-3"),
    ("simulate --elements 0", ["simulate", "--preset", "thesis-rig", "--elements", "0"], "elements"),
    ("simulate --modes 0", ["simulate", "--preset", "thesis-rig", "--modes", "0"], "modes"),
    ("simulate --modes 2.5", ["simulate", "--preset", "thesis-rig", "--modes", "2.5"], "2.5"),
    ("simulate --beta1 -1", ["simulate", "--preset", "thesis-field", "--beta1", "-1"], "beta1"),
    ("simulate --threads -4", ["simulate", "--preset", "thesis-rig", "--threads", "-4"], "-4"),
    ("simulate --start sideways", ["simulate", "--preset", "thesis-rig", "--start", "sideways"], "sideways"),
    ("simulate --preset nope", ["simulate", "--preset", "nope"], "nope"),
    ("simulate --config missing", ["simulate", "--config", "/nonexistent/c.json"], "/nonexistent/c.json"),
    ("simulate --dt 0", ["simulate", "--preset", "thesis-rig", "--dt", "0"], "dt"),
    ("simulate --duration -5", ["simulate", "--preset", "thesis-rig", "--duration", "-5"], "-5"),
    ("simulate --out on a file", ["simulate", "--preset", "thesis-rig", "--out", "@FILE"], "@FILE"),
    ("sweep --speeds -10,-5", ["sweep", "--preset", "thesis-rig", "--speeds", "-10,-5"], "-10"),
    ("sweep --speeds a,b", ["sweep", "--preset", "thesis-rig", "--speeds", "a,b"], "a,b"),
    ("sweep --speeds 5:1:0", ["sweep", "--preset", "thesis-rig", "--speeds", "5:1:0"], "5:1:0"),
    ("sweep --refine -1", ["sweep", "--preset", "thesis-rig", "--refine", "-1"], "-1"),
    ("map --wobs-kn -1,2", ["map", "--preset", "thesis-rig", "--wobs-kn", "-1,2"], "-1"),
    ("modes -n 0", ["modes", "--preset", "thesis-rig", "-n", "0"], "0"),
    ("modes -n 100000", ["modes", "--preset", "thesis-rig", "-n", "100000"], "100000"),
    ("mc --samples 0", ["mc", "--preset", "thesis-rig", "--samples", "0"], "samples = 0"),
    ("mc --samples ten", ["mc", "--preset", "thesis-rig", "--samples", "ten"], "ten"),
    ("mc --seed -1", ["mc", "--preset", "thesis-rig", "--seed", "-1"], "seed"),
    ("mc --first-sample -1", ["mc", "--preset", "thesis-rig", "--first-sample", "-1"], "first_sample"),
    ("mc --eta-dt 0", ["mc", "--preset", "thesis-rig", "--eta-dt", "0"], "eta"),
    ("mc --psd-model 1,2", ["mc", "--preset", "thesis-rig", "--psd-model", "1,2"], "1,2"),
    ("mc --psd-table missing", ["mc", "--preset", "thesis-rig", "--psd-table", "/nonexistent.csv"],
     "/nonexistent.csv"),
    ("mc --eta-std -1", ["mc", "--preset", "thesis-rig", "--eta-std", "-1"], "-1"),
    ("mc-merge missing chunk", ["mc-merge", "/nonexistent/chunk"], "/nonexistent/chunk"),
    ("frf --samples 0", ["frf", "--preset", "thesis-ch6", "--samples", "0"], "samples"),
    ("frf --case 9", ["frf", "--preset", "thesis-ch6", "--case", "9"], "9"),
    ("frf --model XX", ["frf", "--preset", "thesis-ch6", "--model", "XX"], "XX"),
    ("robust-ss --samples 0", ["robust-ss", "--preset", "thesis-ch6", "--samples", "0"], "samples"),
    ("analyze --folds -2", ["analyze", "@RECORD", "--folds", "-2", "--out", "@OUT"], "folds"),
    ("analyze missing record", ["analyze", "/nonexistent/r.csv", "--out", "@OUT"], "/nonexistent/r.csv"),
    ("analyze binary file", ["analyze", "@BINARY", "--out", "@OUT"], "@BINARY"),
    ("analyze empty CSV", ["analyze", "@EMPTY", "--out", "@OUT"], "@EMPTY"),
    ("analyze text in a column", ["analyze", "@TEXTCELL", "--out", "@OUT"], "bit_speed"),
    ("analyze time not increasing", ["analyze", "@BACKWARDS", "--out", "@OUT"], "time"),
    ("analyze ms-as-s record, simulated", ["analyze", "@MS_AS_S", "--out", "@OUT"], "time: sampling rate 1 Hz"),
    ("predict model missing", ["predict", "/nonexistent/model.json", "@RECORD"], "/nonexistent/model.json"),
    ("loop missing record", ["loop", "/nonexistent/r.csv", "--preset", "thesis-rig", "--out", "@OUT"], "/nonexistent/r.csv"),
    ("unknown command", ["simulat"], "simulat"),
]

#: (label, drillpy argv with a readable but implausible record, needle of the warning)
DRILLPY_WARNINGS = [
    ("record in ms labelled s", ["analyze", "@MS_AS_S", "--no-sim", "--out", "@OUT"], "time: sampling rate"),
    ("record in rpm labelled rad/s", ["analyze", "@RPM_AS_RAD", "--no-sim", "--out", "@OUT"], "top speed"),
]

#: (label, drillsim argv, needle)
DRILLSIM_ARGS = [
    ("--threads abc", ["--preset", "thesis-rig", "--threads", "abc"], "abc"),
    ("--threads -4", ["--preset", "thesis-rig", "--threads", "-4"], "-4"),
    ("--job xyz", ["--preset", "thesis-rig", "--job", "xyz"], "xyz"),
    ("--format xyz", ["--preset", "thesis-rig", "--format", "xyz"], "xyz"),
    ("no arguments", [], "config"),
    ("--config and --preset", ["--preset", "thesis-rig", "--config", "@CONFIG"], "preset"),
    ("--preset nope", ["--preset", "nope"], "nope"),
    ("--config missing", ["--config", "/nonexistent/c.json"], "/nonexistent/c.json"),
    ("--out on a file", ["--preset", "thesis-rig", "--out", "@FILE"], "@FILE"),
    ("unknown option", ["--preset", "thesis-rig", "--colour", "red"], "colour"),
]


def _python_cases(cfg: dict) -> list:
    """(label, callable, needle) for the Python API."""
    import drillpy
    from drillpy.model.config import with_overrides
    from drillpy.uncertainty.montecarlo import stochastic_study
    return [
        ("simulate(top_speed='16')", lambda: drillpy.simulate(cfg, top_speed="16"), "top_speed"),
        ("simulate(top_speed=-1)", lambda: drillpy.simulate(cfg, top_speed=-1.0), "-1"),
        ("simulate(top_speed=nan)", lambda: drillpy.simulate(cfg, top_speed=float("nan")), "nan"),
        ("load_config(preset='nope')", lambda: drillpy.load_config(preset="nope"), "nope"),
        ("load_config(path=missing)", lambda: drillpy.load_config(path="/nonexistent.json"), "/nonexistent.json"),
        ("sweep_severity(speeds=[])", lambda: drillpy.sweep_severity(cfg, []), "speeds"),
        ("sweep_severity(speeds=['a'])", lambda: drillpy.sweep_severity(cfg, ["a"]), "speeds"),
        ("with_overrides(modes=-1)", lambda: drillpy.simulate(with_overrides(cfg, modes=-1)), "modes"),
        ("with_overrides(elements=2**40)", lambda: drillpy.simulate(with_overrides(cfg, elements=2**40)),
         "elements"),
        ("stochastic_study(samples=0)", lambda: stochastic_study(cfg, [10.0], 0, 1), "samples = 0"),
        ("stochastic_study(seed='x')", lambda: stochastic_study(cfg, [10.0], 2, "x"), "seed"),
        ("severity_threshold(len mismatch)", lambda: drillpy.severity_threshold([1.0, 2.0], [0.1]), "severities"),
    ]


def _records(tmp: Path) -> dict:
    """The record files the catalogue uses (a CSV version of the test-rig record and broken variants)."""
    from drillpy.records.io import read_record, write_csv
    rec = read_record(RECORD)
    files = {"@RECORD": tmp / "rec.csv"}
    write_csv(rec, files["@RECORD"])
    lines = files["@RECORD"].read_text().splitlines()
    comments = [ln for ln in lines if ln.startswith("#")]
    header = next(ln for ln in lines if not ln.startswith("#"))
    rows = [ln for ln in lines if not ln.startswith("#")][1:]
    cols = header.split(",")

    def variant(name, transform_row=None, text=None, raw=None):
        p = tmp / name
        if raw is not None:
            p.write_bytes(raw)
        elif text is not None:
            p.write_text(text)
        else:
            p.write_text("\n".join(comments + [header] + [transform_row(r.split(",")) for r in rows]) + "\n")
        return p

    it = cols.index("time_s")
    speed_cols = [k for k, c in enumerate(cols) if "speed" in c]

    def scale(k_list, f):
        def t(r):
            return ",".join(str(float(v) * f) if k in k_list and v not in ("", "nan") else v for k, v in enumerate(r))
        return t

    files["@MS_AS_S"] = variant("ms_as_s.csv", scale([it], 1000.0))
    files["@RPM_AS_RAD"] = variant("rpm_as_rad.csv", scale(speed_cols, 60.0 / (2 * 3.141592653589793)))
    files["@BINARY"] = variant("binary.csv", raw=bytes(range(256)) * 8)
    files["@EMPTY"] = variant("empty.csv", text="")
    files["@TEXTCELL"] = variant("textcell.csv", text="\n".join([header] + rows[:50] + [_text_row(rows[50], cols)]
                                                                + rows[51:100]) + "\n")
    files["@BACKWARDS"] = variant("backwards.csv", text="\n".join([header] + rows[:100][::-1]) + "\n")
    return files


def _text_row(row: str, cols: list) -> str:
    v = row.split(",")
    v[cols.index("bit_speed_rad_s")] = "abc"
    return ",".join(v)


def _classify(rc, out, err, needle, warning=False) -> str:
    # warnings printed before an error explain it (analyze of an implausible record): not part of it
    text = "\n".join(ln for ln in err.strip().splitlines() if "warning:" not in ln)
    if "Traceback" in err or "Traceback" in out or rc is None or rc < 0 or "NaN" in out:
        return "crash"
    if rc == 0:
        warn = [ln for ln in err.splitlines() if "warning" in ln]
        if warning and any(_names(ln, needle) for ln in warn):
            return "flagged"
        return "silent"
    one_line = text.count("\n") == 0
    return "clear" if rc == 2 and one_line and _names(text, needle) else "unclear"


def _names(text: str, needle) -> bool:
    return any(n in text for n in ((needle,) if isinstance(needle, str) else needle))


def _run(argv, timeout=TIMEOUT_S):
    t0 = time.perf_counter()
    try:
        r = subprocess.run(argv, capture_output=True, text=True, timeout=timeout,
                           env=_tree_env())
        return r.returncode, r.stdout, r.stderr, time.perf_counter() - t0
    except subprocess.TimeoutExpired:
        return None, "", "timeout", time.perf_counter() - t0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--only", help="run the entries whose label contains this word")
    ap.add_argument("--list", action="store_true", help="print every entry with its outcome")
    args = ap.parse_args()
    if any((REPO / "python" / "drillpy").glob("_core*.so")):  # in-tree build, else the installed drillpy
        sys.path.insert(0, str(REPO / "python"))
    drillsim = _drillsim()
    tmp = Path(tempfile.mkdtemp(prefix="bad_inputs_"))
    base = _base_config()
    files = _records(tmp)
    files["@FILE"] = tmp / "a_file"
    files["@FILE"].write_text("x")
    files["@CONFIG"] = tmp / "good.json"
    files["@CONFIG"].write_text(json.dumps(base))

    def subst(argv, k):
        out = []
        for a in argv:
            if a == "@OUT":
                a = str(tmp / f"out{k}")
            out.append(str(files[a]) if isinstance(a, str) and a in files else a)
        return out

    results = []  # (group, label, outcome, detail)
    k = 0
    for label, edit, needle in CONFIG_EDITS:
        c = copy.deepcopy(base)
        edit(c)
        p = tmp / f"cfg{k}.json"
        p.write_text(json.dumps(c))
        for tool, argv in (("drillsim", [drillsim, "--config", str(p), "--out", str(tmp / f"o{k}")]),
                           ("drillpy", [sys.executable, "-m", "drillpy", "simulate", "--config", str(p)])):
            results.append((f"config ({tool})", label, argv, needle, False))
        k += 1
    for label, text, needle in _config_text_cases(base):
        p = tmp / f"cfg{k}.json"
        p.write_text(text)
        for tool, argv in (("drillsim", [drillsim, "--config", str(p)]),
                           ("drillpy", [sys.executable, "-m", "drillpy", "simulate", "--config", str(p)])):
            results.append((f"config ({tool})", label, argv, needle, False))
        k += 1
    for label, argv, needle in DRILLPY_ARGS:
        results.append(("drillpy options", label, [sys.executable, "-m", "drillpy", *subst(argv, k)],
                        subst([needle], k)[0], False))
        k += 1
    for label, argv, needle in DRILLPY_WARNINGS:
        results.append(("records (plausibility)", label, [sys.executable, "-m", "drillpy", *subst(argv, k)],
                        needle, True))
        k += 1
    for label, argv, needle in DRILLSIM_ARGS:
        results.append(("drillsim options", label, [drillsim, *subst(argv, k)], subst([needle], k)[0], False))
        k += 1

    rows = []
    for group, label, argv, needle, warning in results:
        if args.only and args.only not in label:
            continue
        rc, out, err, dt = _run(argv)
        rows.append((group, label, _classify(rc, out, err, needle, warning), (err.strip().splitlines() or [""])[-1],
                     dt))
    for label, fn, needle in _python_cases(base):
        if args.only and args.only not in label:
            continue
        t0 = time.perf_counter()
        try:
            fn()
            outcome, msg = "silent", ""
        except ValueError as e:
            msg = str(e)
            outcome = "clear" if _names(msg, needle) and "\n" not in msg else "unclear"
        except Exception as e:  # noqa: BLE001 -- any other exception type is what the catalogue looks for
            outcome, msg = "crash", f"{type(e).__name__}: {e}"
        rows.append(("Python API", label, outcome, msg, time.perf_counter() - t0))
    shutil.rmtree(tmp, ignore_errors=True)

    kinds = ("clear", "flagged", "unclear", "silent", "crash")
    if args.list:
        for group, label, outcome, msg, dt in rows:
            print(f"{outcome:8s} {group:24s} {label:34s} {dt:6.1f} s  {msg[:150]}")
        print()
    groups = sorted({r[0] for r in rows})
    print(f"{'entry point':26s}" + "".join(f"{k:>9s}" for k in kinds))
    for g in groups:
        print(f"{g:26s}" + "".join(f"{sum(1 for r in rows if r[0] == g and r[2] == k):9d}" for k in kinds))
    print(f"{'total (' + str(len(rows)) + ')':26s}" + "".join(f"{sum(1 for r in rows if r[2] == k):9d}"
                                                             for k in kinds))
    bad = [r for r in rows if r[2] in ("unclear", "silent", "crash")]
    for group, label, outcome, msg, _ in bad:
        print(f"  {outcome}: {group}: {label}: {msg[:200]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

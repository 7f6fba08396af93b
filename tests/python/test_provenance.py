"""Every output a command writes says which drillpy made it, with which command line and when."""
from datetime import datetime

import json

import pytest

import drillpy
from conftest import run_cli
from drillpy.provenance import header, provenance, running_command

FAST = ["--no-progress"]
#: command -> (arguments before --out, the JSON files written, the options the provenance records)
COMMANDS = {
    "simulate": (["simulate", "--preset", "thesis-rig", "--duration", "10", "--transient", "5", "--start", "rigid"],
                 ["summary.json"], {"start": "rigid"}),
    "sweep": (["sweep", "--preset", "thesis-field", "--speeds", "8,14,20", "--duration", "40", "--transient", "20",
               "--start", "rigid"], ["sweep.json"], {"start": "rigid"}),
    "map": (["map", "--preset", "thesis-field", "--speeds-rpm", "60,120", "--wobs-kn", "50,100", "--duration", "40",
             "--transient", "20"], ["map.json"], {"start": "rest"}),
    "frf": (["frf", "--preset", "thesis-ch6", "--model", "SM_CB2", "--case", "4", "--samples", "4", "--seed", "5",
             "--freqs", "0.1:10:20"], ["envelope.json"], {"seed": 5, "samples": 4, "case": 4}),
    "robust-ss": (["robust-ss", "--preset", "thesis-ch6", "--cb-modes", "6,3", "--dt", "1e-3", "--duration", "20",
                   "--transient", "10", "--samples", "2", "--speeds", "8,20", "--seed", "7", "--delta", "0.2"],
                  ["robust_ss.json"], {"seed": 7, "delta": 0.2, "samples": 2}),
    "mc": (["mc", "--preset", "thesis-field", "--modes", "10", "--samples", "2", "--speeds", "8,20", "--seed", "3",
            "--warmup", "20", "--duration", "30", "--transient", "10"], ["mc.json", "mc_samples.json"],
           {"seed": 3, "samples": 2}),
}


def check(prov: dict, argv: list[str]) -> None:
    assert prov["drillpy_version"] == drillpy.__version__
    stamp = datetime.fromisoformat(prov["timestamp"])
    assert stamp.utcoffset() is not None and stamp.utcoffset().total_seconds() == 0
    assert prov["command"].startswith("drillpy " + argv[0])
    assert prov["python"].count(".") == 2


@pytest.mark.parametrize("name", COMMANDS)
def test_every_json_a_command_writes_has_provenance(name, tmp_path):
    argv, files, options = COMMANDS[name]
    out = tmp_path / "out"
    r = run_cli(*argv, *FAST, "--out", str(out))
    assert r.returncode == 0, r.stderr
    written = sorted(p.name for p in out.glob("*.json"))
    assert written == sorted(files)
    for f in files:
        prov = json.loads((out / f).read_text())["provenance"]
        check(prov, argv)
        assert "--out" in prov["command"]
        for k, v in options.items():
            assert prov[k] == v, (f, k)
    for png in out.glob("*.png"):
        assert f"drillpy {drillpy.__version__}".encode() in png.read_bytes()[:4096]  # Software metadata
    if name == "simulate":
        first, columns = (out / "series.csv").read_text().splitlines()[:2]
        assert first.startswith(f"# drillpy {drillpy.__version__}, drillpy simulate ")
        assert columns.startswith("time_s,")


def test_analyze_and_predict_outputs_have_provenance(tmp_path):
    from _testrig import sample175_path
    from drillpy.jsonio import jsonable
    from drillpy.model.config import load_config
    from drillpy.records import rigsim
    rec = str(sample175_path())
    argv = ["analyze", f"{rec}@0:5", f"{rec}@5:10"]
    r = run_cli(*argv, "--out", str(tmp_path / "s"))
    assert r.returncode == 0, r.stderr
    check(json.loads((tmp_path / "s" / "samples.json").read_text())["provenance"], argv)
    last = (tmp_path / "s" / "samples.md").read_text().splitlines()[-1]
    assert last.startswith(f"*drillpy {drillpy.__version__}, `drillpy analyze ")

    model = rigsim.RigModel(load_config(preset="thesis-rig")["law"], 0.3, "constant")
    (tmp_path / "model.json").write_text(json.dumps(jsonable(model.to_dict(top_speed=8.0, wob=560.0))))
    argv = ["predict", str(tmp_path / "model.json"), rec, "--t0", "30", "--t1", "36"]
    r = run_cli(*argv, "--out", str(tmp_path / "p"))
    assert r.returncode == 0, r.stderr
    check(json.loads((tmp_path / "p" / "summary.json").read_text())["provenance"], argv)


def test_version():
    r = run_cli("--version")
    assert r.returncode == 0 and r.stdout.strip() == f"drillpy {drillpy.__version__}"


def test_provenance_record_and_header():
    with running_command(["sweep", "--speeds", "8, 14"]):
        p = provenance(seed=3, delta=None)
    assert p["command"] == "drillpy sweep --speeds '8, 14'" and p["seed"] == 3 and "delta" not in p
    assert header(p) == f"# drillpy {drillpy.__version__}, drillpy sweep --speeds '8, 14', {p['timestamp']}"
    assert provenance()["command"] != p["command"]  # outside the command: sys.argv

"""Behaviour unchanged across a restructuring: every CLI command's JSON output, hashed.

Runs a fixed set of short ``drillpy`` commands on the presets (and on the test-rig record), collects
every JSON document each one prints (``--json``) or writes (``*.json`` under ``--out``), removes what
legitimately changes from run to run (the ``provenance`` block: time, command line, version, host;
the record is named by its resolved path, so a symlinked ``shared`` gives the same documents),
and records a SHA-256 of each document in canonical form (sorted keys, the numbers as written).

    PYTHONPATH=python python3 scripts/cli_identity.py --write /tmp/before.json     # on the old tree
    PYTHONPATH=python python3 scripts/cli_identity.py --compare /tmp/before.json   # on the new tree

``--compare`` prints one line per document (``same`` / ``DIFFERENT`` / ``missing`` / ``new``) and
exits with status 1 if any differs. The commands run single-threaded so that the numbers do not
depend on the thread count's reduction order (they do not, by design; this keeps the check strict).
"""
from __future__ import annotations

import argparse
import hashlib
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

RECORD = (Path(__file__).resolve().parents[1].parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat").resolve()

#: (name, arguments after ``drillpy``); ``{out}`` is replaced by the command's own fresh folder,
#: ``{out:NAME}`` by an earlier command's folder, ``{record}`` by RECORD.
COMMANDS = [
    ("modes", ["modes", "--preset", "thesis-field", "--elements", "50", "-n", "5", "--json"]),
    ("simulate", ["simulate", "--preset", "thesis-field", "--top-speed", "16", "--duration", "20",
                  "--out", "{out}", "--json"]),
    ("sweep", ["sweep", "--preset", "thesis-field", "--speeds", "10:20:3", "--duration", "30", "--json"]),
    ("map", ["map", "--preset", "thesis-field", "--speeds-rpm", "60:160:3", "--wobs-kn", "50:200:3",
             "--duration", "20", "--out", "{out}", "--json"]),
    ("frf", ["frf", "--preset", "thesis-ch6", "--model", "SM_CB2", "--case", "4", "--samples", "50",
             "--json"]),
    ("mc", ["mc", "--preset", "thesis-field", "--samples", "6", "--speeds", "10:20:3", "--duration", "20",
            "--transient", "10", "--seed", "1", "--out", "{out}", "--json"]),
    ("control", ["control", "--preset", "thesis-field", "--drive-inertia", "2000", "--torque-limit", "50000",
                 "--controllers", "soft_speed", "--samples", "3", "--validation-samples", "3", "--speeds",
                 "14:20:2", "--duration", "20", "--transient", "10", "--out", "{out}", "--json"]),
    ("analyze", ["analyze", "{record}", "--out", "{out}", "--json"]),
    ("predict", ["predict", "{out:analyze}/model.json", "{record}", "--t0", "20", "--t1", "30", "--out", "{out}",
                 "--json"]),
    ("loop", ["loop", "{record}", "--preset", "thesis-rig", "--out", "{out}", "--json"]),
    ("report", ["report", "--preset", "thesis-field", "--elements", "50", "--modes", "10", "--duration", "40",
                "--transient", "20", "--out", "{out}", "--json"]),
]

VOLATILE = {"provenance"}


def _strip(x):
    if isinstance(x, dict):
        return {k: _strip(v) for k, v in x.items() if k not in VOLATILE}
    if isinstance(x, list):
        return [_strip(v) for v in x]
    return x


def digest(doc) -> str:
    """SHA-256 of a JSON document without its provenance, keys sorted."""
    text = json.dumps(_strip(doc), sort_keys=True, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def _stdout_documents(text: str) -> list:
    try:
        return [json.loads(text)]
    except json.JSONDecodeError:
        pass
    docs, dec, i = [], json.JSONDecoder(), 0
    while (i := text.find("{", i)) >= 0:
        try:
            doc, end = dec.raw_decode(text, i)
        except json.JSONDecodeError:
            i += 1
            continue
        docs.append(doc)
        i = end
    return docs


def run_one(name: str, args: list, root: Path, env: dict) -> dict:
    """Hashes of the JSON documents one command prints and writes, keyed ``name:source``."""
    out = root / name
    argv = []
    for a in args:
        for other, _ in COMMANDS:
            a = a.replace("{out:%s}" % other, str(root / other))
        argv.append(a.replace("{out}", str(out)).replace("{record}", str(RECORD)))
    proc = subprocess.run([sys.executable, "-m", "drillpy", *argv], capture_output=True, text=True, env=env)
    if proc.returncode != 0:
        return {f"{name}:exit": f"status {proc.returncode}: {proc.stderr.strip()[-300:]}"}
    hashes = {f"{name}:stdout[{k}]": digest(d) for k, d in enumerate(_stdout_documents(proc.stdout))}
    for path in sorted(out.rglob("*.json")) if out.exists() else []:
        hashes[f"{name}:{path.relative_to(out)}"] = digest(json.loads(path.read_text()))
    return hashes


def collect(names=None) -> dict:
    env = dict(os.environ, OMP_NUM_THREADS="1", OPENBLAS_NUM_THREADS="1", MPLBACKEND="Agg")
    result = {}
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in COMMANDS:
            if names and name not in names:
                continue
            hashes = run_one(name, args, Path(tmp), env)
            print(f"{name}: {len(hashes)} document(s)", file=sys.stderr)
            result.update(hashes)
    return result


def compare(before: dict, after: dict) -> int:
    bad = 0
    for key in sorted(set(before) | set(after)):
        if key not in after:
            state = "missing"
        elif key not in before:
            state = "new"
        else:
            state = "same" if before[key] == after[key] else "DIFFERENT"
        bad += state != "same"
        print(f"{state:9s} {key}")
    print(f"{len(before)} before, {len(after)} after, {bad} not identical")
    return 1 if bad else 0


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    group = ap.add_mutually_exclusive_group(required=True)
    group.add_argument("--write", type=Path, help="write the hashes of this tree's outputs to FILE")
    group.add_argument("--compare", type=Path, help="compare this tree's outputs with FILE's hashes")
    ap.add_argument("--only", nargs="*", help="run only these commands (names of COMMANDS)")
    a = ap.parse_args(argv)
    hashes = collect(a.only)
    if a.write:
        a.write.write_text(json.dumps(hashes, indent=1, sort_keys=True) + "\n")
        print(f"{len(hashes)} documents -> {a.write}")
        return 0
    return compare(json.loads(a.compare.read_text()), hashes)


if __name__ == "__main__":
    sys.exit(main())

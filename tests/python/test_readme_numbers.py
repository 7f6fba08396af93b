"""Issue 31 item 1: the README's headline numbers are the lines the commands print."""
import json
import re
from pathlib import Path

import pytest

from conftest import run_cli

README = (Path(__file__).resolve().parents[2] / "README.md").read_text()


def _printed_threshold(preset: str) -> str:
    r = run_cli("sweep", "--preset", preset, "--speeds", "6:27:22", "--no-progress")
    assert r.returncode == 0, r.stderr
    return next(line for line in r.stdout.splitlines() if line.startswith("SS > 0.5 below"))


@pytest.mark.parametrize("preset", ["thesis-field", "thesis-ch4"])
def test_readme_threshold_is_the_printed_line(preset):
    line = _printed_threshold(preset)
    assert re.fullmatch(r"SS > 0\.5 below \d+\.\d\d \+- 0\.0[0-2] rad/s \(\d+\.\d \+- 0\.\d RPM, bisection\)", line)
    assert f"`{line}" in README  # quoted verbatim in the headline


def test_readme_frequencies_are_the_printed_ones():
    r = run_cli("modes", "--preset", "thesis-field", "-n", "5", "--json")
    assert r.returncode == 0, r.stderr
    f = json.loads(r.stdout)["frequencies_hz"]
    assert "natural frequencies " + ", ".join(f"{x:.4f}" for x in f) + " Hz" in README


def test_thesis_threshold_only_beside_the_configuration_that_reproduces_it():
    from drillpy.model.config import load_config, with_overrides
    from drillpy.reports.preset import thesis_threshold
    assert thesis_threshold(load_config(preset="thesis-ch4")) == 16.0
    assert thesis_threshold(load_config(preset="thesis-field")) is None
    assert thesis_threshold(with_overrides(load_config(preset="thesis-ch4"), modes=20)) is None

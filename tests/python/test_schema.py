"""The configuration's JSON Schema: the shipped file is drillsim's, the presets satisfy it, and it
refuses what the engine's parser refuses."""
import json
import re
import subprocess
from pathlib import Path

import jsonschema
import pytest

import drillpy

SCHEMA_FILE = Path(drillpy.__file__).parent / "model" / "config.schema.json"


@pytest.fixture(scope="module")
def validator():
    schema = json.loads(SCHEMA_FILE.read_text())
    jsonschema.Draft202012Validator.check_schema(schema)
    return jsonschema.Draft202012Validator(schema)


def test_shipped_schema_is_drillsims(drillsim):
    r = subprocess.run([drillsim, "--schema"], capture_output=True, text=True)
    assert r.returncode == 0, r.stderr
    assert SCHEMA_FILE.read_text() == r.stdout, "stale: run scripts/generate-schema.sh"


@pytest.mark.parametrize("name", drillpy.preset_names())
def test_presets_satisfy_the_schema(validator, name):
    config = drillpy.load_config(preset=name)
    validator.validate(config)
    validator.validate({"$schema": "config.schema.json", **config})


@pytest.mark.parametrize("path, value, needle", [
    (("operation", "colour"), 3, "operation.colour = 3: unknown key"),
    (("string", "sections", 0, "density_kg_m3"), "heavy", 'density_kg_m3 = "heavy": must be a number'),
    (("damping", "ratios", 0), 5.0, "damping.ratios[0] = 5: must be at most 1"),
    (("operation", "wob_n"), -3.0, "operation.wob_n = -3: must not be negative"),
    (("rom", "modes"), 4294967297, "rom.modes = 4294967297"),
    (("law", "type"), "magic", 'law.type = "magic"'),
    (("law", "beta3"), 0.5, "law.beta3 = 0.5: unknown key"),
    (("top_drive",), {"type": "motor", "slope_nms_rad": 50.0}, "top_drive.inertia_kg_m2: missing"),
])
def test_schema_refuses_what_the_parser_refuses(validator, path, value, needle):
    config = drillpy.load_config(preset="thesis-field")
    node = config
    for key in path[:-1]:
        node = node[key]
    node[path[-1]] = value
    with pytest.raises(ValueError, match=re.escape(needle)):
        drillpy.load_config(config=config)
    assert not validator.is_valid(config)

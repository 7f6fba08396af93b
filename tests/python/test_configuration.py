"""The typed configuration (issue 32): attribute access checked against the schema, changed by copy,
the same JSON as the normalized dict."""
import json
import pickle

import pytest

import drillpy
from drillpy.model.config import normalize, thesis_law, with_overrides
from drillpy.model.configuration import Configuration


@pytest.fixture(scope="module")
def field():
    return Configuration.load(preset="thesis-field")


def test_attribute_access(field):
    d = drillpy.load_config(preset="thesis-field")
    assert field.simulation.dt_s == d["simulation"]["dt_s"]
    assert field.law.type == "hysteretic" and field.law.beta1 == 0.14
    assert [s.name for s in field.string.sections] == ["DP", "BHA"]
    assert field.string.sections[1].elements == 9
    assert field.damping.ratios == (0.095, 0.02)
    assert field.name == "thesis-field"
    # blocks the normalized dict leaves out take the schema's default: what the engine uses
    assert field.top_drive.type == "ideal" and field.axial.type == "none"


@pytest.mark.parametrize("expr, needle", [
    (lambda c: c.simulation.dt_ms, "simulation.dt_ms: no such key"),
    (lambda c: c.colour, "colour: no such key"),
    (lambda c: c.string.sections[0].lenght_m, "string.sections[0].lenght_m: no such key"),
    (lambda c: c.law.c0, "law.c0: not a key of law.type = 'hysteretic'"),
    (lambda c: c.craig_bampton, "craig_bampton: not set"),
])
def test_unknown_key_names_it(field, expr, needle):
    with pytest.raises(AttributeError, match=needle.replace("[", r"\[").replace("]", r"\]").replace(".", r"\.")):
        expr(field)


def test_get_gives_a_default_for_an_unset_key_but_refuses_an_unknown_one(field):
    assert field.get("craig_bampton") is None and "craig_bampton" not in field
    assert field.law.get("beta1") == 0.14
    assert field.law.get("c0") is None  # a key of another law type
    assert field.top_drive.get("inertia_kg_m2") is None
    with pytest.raises(AttributeError, match="law.bta1: no such key"):
        field.law.get("bta1")
    assert not hasattr(field.law, "c0")


def test_read_only(field):
    with pytest.raises(AttributeError, match="read-only"):
        field.simulation.dt_s = 1.0
    with pytest.raises(AttributeError, match="read-only"):
        field.law = {}


@pytest.mark.parametrize("name", drillpy.preset_names())
def test_round_trip_identical_to_normalize(name):
    d = drillpy.load_config(preset=name)
    c = Configuration.from_dict(d)
    assert c.to_dict() == normalize(d) == d
    assert json.dumps(c.to_dict()) == json.dumps(normalize(d))  # the same JSON text, key order included
    assert Configuration.from_json(c.to_json()) == c
    assert c.to_json() == json.dumps(d, allow_nan=False)
    assert pickle.loads(pickle.dumps(c)) == c
    assert Configuration.of(d) == c and Configuration.of(c) is c and Configuration.of(c.engine()) == c


def test_a_view_never_leaks_its_data(field):
    d = field.to_dict()
    d["simulation"]["dt_s"] = 1.0
    field.simulation.to_dict()["dt_s"] = 1.0
    assert field.simulation.dt_s == 5.12e-4


def test_replace_is_a_copy(field):
    c = field.replace({"simulation.duration_s": 20.0, "simulation.transient_s": 10.0},
                      law=thesis_law("tucker_wang"))
    assert (c.simulation.duration_s, c.simulation.transient_s, c.law.type) == (20.0, 10.0, "tucker_wang")
    assert (field.simulation.duration_s, field.law.type) == (200.0, "hysteretic")
    assert c.normalized().law.c0 == 4700.0
    assert field.replace(sweep=None).get("sweep") is None
    assert field.replace({"top_drive.type": "motor"}).top_drive.type == "motor"
    with pytest.raises(AttributeError, match="simulation.dt_ms: no such key"):
        field.replace({"simulation.dt_ms": 1e-3})
    with pytest.raises(AttributeError, match="colour: no such key"):
        field.replace(colour={})


def test_with_overrides_as_the_function(field):
    d = drillpy.load_config(preset="thesis-field")
    kw = dict(elements=200, duration=40.0, top_speed=12.0, law="tucker_wang")
    c = field.with_overrides(**kw)
    assert c.to_dict() == with_overrides(d, **kw)
    assert [s.elements for s in c.string.sections] == [182, 18] and c.simulation.transient_s == 20.0
    with pytest.raises(ValueError, match="beta1"):
        field.with_overrides(law="tucker_wang", beta1=0.1)


def test_keys_come_from_the_schema():
    schema = json.loads((drillpy.model.configuration.SCHEMA_FILE).read_text())
    top = set(schema["properties"])
    c = Configuration({"string": {"sections": []}})
    for key in top:
        assert c.get(key, "unset") is not None  # every key of the schema is a name; none raises

"""Configurations: presets, overrides, and errors that name the field and the value."""
import json
import time

import pytest

import drillpy
from drillpy.model.config import thesis_law, with_overrides


def test_presets_load_normalized():
    assert set(drillpy.preset_names()) == {"thesis-field", "thesis-ch4", "thesis-rig", "thesis-ch6", "rgd-field",
                                             "rgd-rig"}
    c = drillpy.load_config(preset="thesis-field")
    assert [s["elements"] for s in c["string"]["sections"]] == [91, 9]
    assert c["law"]["speed_unit"] == "rpm" and c["law"]["beta1"] == 0.14
    assert c["simulation"]["dt_s"] == pytest.approx(5.12e-4)
    assert c["operation"]["bit_viscous_nms"] == 0.0 and c["operation"]["string_friction_nm"] == 0.0


def test_file_round_trip(tmp_path):
    c = drillpy.load_config(preset="thesis-rig")
    p = tmp_path / "rig.json"
    p.write_text(json.dumps(c))
    assert drillpy.load_config(path=p) == c


def test_elements_override_splits_by_length():
    c = with_overrides(drillpy.load_config(preset="thesis-field"), elements=200)
    assert [s["elements"] for s in c["string"]["sections"]] == [182, 18]


def test_thesis_laws():
    assert thesis_law("hysteretic", 0.56)["beta1"] == 0.56
    assert thesis_law("tucker_wang")["c0"] == 4700.0


@pytest.mark.parametrize("edit, field", [
    (lambda c: c["string"]["sections"][0].update(length_m=-1.0), "string.sections[0].length_m = -1"),
    (lambda c: c["string"]["sections"][1].update(inner_radius_m=0.2), "string.sections[1].inner_radius_m = 0.2"),
    (lambda c: c["string"]["sections"][0].update(elements=0), "string.sections[0].elements = 0"),
    (lambda c: c["string"]["sections"][0].update(outer_radius_m=float("nan")), "outer_radius_m"),
    (lambda c: c["rom"].update(modes=101), "rom.modes = 101"),
    (lambda c: c["law"].update(type="coulomb"), 'law.type = "coulomb"'),
    (lambda c: c["law"].pop("b2"), "law.b2: missing"),
    (lambda c: c.pop("string"), "config.string: missing"),
    (lambda c: c["simulation"].update(dt_s=0.05), "simulation.dt_s = 0.05"),
    (lambda c: c.update(colour="red"), 'config.colour = "red": unknown key'),
    (lambda c: c["operation"].update(string_friction_nm=-1.5),
     "operation.string_friction_nm = -1.5: must not be negative"),
    (lambda c: c["operation"].update(string_friction_nm="high"), 'operation.string_friction_nm = "high"'),
    (lambda c: c["damping"].update(ratios=[5.0, 0.02]), "damping.ratios[0] = 5: must be at most 1"),
    (lambda c: c["operation"].update(top_speed_rad_s=0.0), "operation.top_speed_rad_s = 0: must be positive"),
    (lambda c: c["operation"].update(top_speed_rad_s=-8.0), "operation.top_speed_rad_s = -8: must be positive"),
    (lambda c: c.update(damping={"type": "rayleigh", "pairs": [[0.1, 0.05], [1.0, 2.0]]}),
     "damping.pairs[1].ratio = 2: must be at most 1"),
])
def test_bad_config_names_field_and_value(edit, field):
    c = drillpy.load_config(preset="thesis-field")
    edit(c)
    with pytest.raises(ValueError) as e:
        drillpy.simulate(c)
    assert field in str(e.value)


def test_malformed_json_file(tmp_path):
    p = tmp_path / "bad.json"
    p.write_text('{"string": [1, 2')
    with pytest.raises(ValueError, match="malformed JSON"):
        drillpy.load_config(path=p)
    with pytest.raises(ValueError, match="no such file"):
        drillpy.load_config(path=tmp_path / "missing.json")


@pytest.mark.parametrize("levels", [65, 200_000])
def test_a_json_nested_beyond_the_limit_is_refused_at_once_naming_the_file(tmp_path, levels):
    p = tmp_path / "deep.json"
    p.write_text("[" * levels + "]" * levels)  # issue 31: a recursion error named nothing
    t0 = time.perf_counter()
    with pytest.raises(ValueError) as e:
        drillpy.load_config(path=p)
    assert time.perf_counter() - t0 < 5.0
    assert str(e.value) == (f"config = {str(p)!r}: JSON nested too deep: more than 64 levels of arrays and objects "
                            "(a configuration has 4)")


def test_the_nesting_limit_is_the_engines(tmp_path):
    from drillpy import _core
    from drillpy.model.config import MAX_JSON_DEPTH
    p = tmp_path / "limit.json"
    p.write_text("[" * MAX_JSON_DEPTH + "]" * MAX_JSON_DEPTH)  # deep as allowed: refused as a configuration
    with pytest.raises(ValueError) as e:
        drillpy.load_config(path=p)
    assert "nested too deep" not in str(e.value)
    with pytest.raises(ValueError, match=f"^config: JSON nested too deep: more than {MAX_JSON_DEPTH} levels"):
        _core.Config("[" * (MAX_JSON_DEPTH + 1) + "]" * (MAX_JSON_DEPTH + 1))
    with pytest.raises(ValueError) as e:
        _core.Config("[" * MAX_JSON_DEPTH + "]" * MAX_JSON_DEPTH)
    assert "nested too deep" not in str(e.value)

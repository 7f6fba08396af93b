"""Records: the MATLAB reader on sample 175, the CSV format (round trip, units) and every bad input."""
import math

import numpy as np
import pytest
from scipy.io import savemat

from _testrig import sample175_path, sample175_raw
from drillpy.cli import main
from drillpy.records.io import RPM, Flag, Record, read_csv, read_mat, read_record, write_csv


def test_sample175_channels_units_and_rate():
    r = read_mat(sample175_path())
    assert len(r) == 40000 and r.channels == ("bit_speed", "top_speed", "torque_on_bit", "wob")
    assert r.units["bit_speed"] == "rpm" and r.units["torque_on_bit"] == "Nm"
    assert r.sample_rate_hz == pytest.approx(1000.0, rel=1e-9)
    assert r.time_s[0] == 0.0 and r.duration_s == pytest.approx(39.999)
    # README: bit speed between about 0 and 200 RPM; stored in rad/s
    assert np.max(r.bit_speed) == pytest.approx(200.013987 * math.pi / 30, rel=1e-9)
    assert 500 < np.mean(r.wob) < 650  # WOB around about 570 N
    assert r.provenance["variables"]["time"] == "Time_Sample_175_complete"
    assert not any(f.any() for f in r.flags.values())  # no NaN in the file


def _synthetic(n=200, channels=("bit_speed", "top_speed", "torque_on_bit", "wob")):
    t = np.arange(n) * 1e-3
    data = {"bit_speed": 5 + 3 * np.sin(20 * t), "top_speed": np.full(n, 8.0), "torque_on_bit": 2 + 0.1 * t,
            "wob": 550 + 10 * np.cos(5 * t)}
    return Record(time_s=t, **{c: data[c] for c in channels})


@pytest.mark.parametrize("unit", ["rad_s", "rpm"])
def test_csv_round_trip_is_exact(tmp_path, unit):
    r = _synthetic()
    r.torque_on_bit[5] = np.nan  # a missing value survives as an empty cell
    p = write_csv(r, tmp_path / "r.csv", speed_unit=unit)
    header = p.read_text().splitlines()[0]
    assert header == f"time_s,bit_speed_{unit},top_speed_{unit},torque_on_bit_Nm,wob_N"
    back = read_csv(p)
    for c in ("time_s",) + r.channels:
        np.testing.assert_allclose(getattr(back, c), getattr(r, c), rtol=1e-15, atol=0, equal_nan=True)
    assert back.flags["torque_on_bit"][5] == Flag.NONFINITE


def test_csv_units_are_converted_to_si(tmp_path):
    p = tmp_path / "u.csv"
    p.write_text("# a comment\ntime_ms,bit_speed_rpm,torque_on_bit_kNm,wob_kN\n0,60,0.002,0.5\n1,30,0.003,0.6\n")
    r = read_csv(p)
    np.testing.assert_allclose(r.time_s, [0, 1e-3])
    np.testing.assert_allclose(r.bit_speed, [2 * math.pi, math.pi])
    np.testing.assert_allclose(r.torque_on_bit, [2.0, 3.0])
    np.testing.assert_allclose(r.wob, [500.0, 600.0])
    assert r.top_speed is None and r.provenance["comments"] == ["a comment"]
    with pytest.raises(ValueError, match="channel 'top_speed' is missing"):
        r.channel("top_speed")


def test_sample175_survives_csv(tmp_path):
    r = sample175_raw().select(10, 11)
    back = read_record(write_csv(r, tmp_path / "s.csv", speed_unit="rpm"))
    np.testing.assert_allclose(back.bit_speed * RPM, r.bit_speed * RPM, rtol=1e-12)


BAD_CSV = {
    "empty.csv": ("", "empty file"),
    "header_only.csv": ("time_s,bit_speed_rad_s\n", "no data rows"),
    "no_time.csv": ("bit_speed_rad_s,wob_N\n1,2\n", "no time"),
    "no_data.csv": ("time_s\n0\n1\n", "no data channel"),
    "unknown_unit.csv": ("time_s,bit_speed_deg_s\n0,1\n", "'deg_s': unknown unit for bit_speed"),
    "unknown_quantity.csv": ("time_s,bitspeed_rpm\n0,1\n", "'bitspeed_rpm': unknown quantity"),
    "duplicate.csv": ("time_s,bit_speed_rpm,bit_speed_rad_s\n0,1,2\n", "are both bit_speed"),
    "unequal.csv": ("time_s,bit_speed_rpm,wob_N\n0,1,2\n1,2\n", "line 3 has 2 cells but the header has 3"),
    "non_numeric.csv": ("time_s,bit_speed_rpm,wob_N\n0,1,2\n1,fast,2\n", "line 3, column 'bit_speed_rpm': 'fast'"),
}


@pytest.mark.parametrize("name", sorted(BAD_CSV))
def test_bad_csv_gives_one_clear_error(tmp_path, name):
    text, msg = BAD_CSV[name]
    p = tmp_path / name
    p.write_text(text)
    with pytest.raises(ValueError, match=msg.replace("(", r"\(")) as e:
        read_record(p)
    assert name in str(e.value)


def test_bad_matlab_files(tmp_path):
    t = np.arange(10) * 1e-3
    cases = {
        "none.mat": ({"foo": t}, "no time"),
        "no_channels.mat": ({"Time_Sample_1_complete": t, "foo": t}, "no data channel"),
        "unequal.mat": ({"Time_Sample_1_complete": t, "Bit_Speed_Sample_1_complete": t[:5]}, "unequal lengths"),
        "text.mat": ({"Time_Sample_1_complete": t, "WOB_Sample_1_complete": "heavy"}, "is not numeric"),
        "matrix.mat": ({"Time_Sample_1_complete": t, "WOB_Sample_1_complete": np.ones((3, 4))}, "expected a vector"),
        "two_times.mat": ({"Time_a": t, "Time_b": t, "WOB_x": t}, "several variables could be time"),
    }
    for name, (data, msg) in cases.items():
        savemat(tmp_path / name, data)
        with pytest.raises(ValueError, match=msg):
            read_mat(tmp_path / name)
    savemat(tmp_path / "empty_vars.mat", {"Time_Sample_1_complete": np.zeros(0), "WOB_Sample_1_complete": np.zeros(0)})
    with pytest.raises(ValueError, match="is empty"):
        read_mat(tmp_path / "empty_vars.mat")
    (tmp_path / "empty.mat").write_bytes(b"")
    with pytest.raises(ValueError, match="empty.mat"):
        read_mat(tmp_path / "empty.mat")
    (tmp_path / "junk.mat").write_bytes(b"not a matlab file at all" * 10)
    with pytest.raises(ValueError, match="not a readable MATLAB file"):
        read_mat(tmp_path / "junk.mat")
    with pytest.raises(ValueError, match="no such file"):
        read_record(tmp_path / "absent.mat")
    with pytest.raises(ValueError, match="unknown format '.xlsx'"):
        read_record(tmp_path / "r.xlsx")
    # other variable names, given explicitly, with their unit
    savemat(tmp_path / "named.mat", {"t": t, "w": 2 * t})
    r = read_mat(tmp_path / "named.mat", variables={"time": ("t", "s"), "bit_speed": ("w", "rpm")})
    np.testing.assert_allclose(r.bit_speed, 2 * t * math.pi / 30)
    with pytest.raises(ValueError, match="unknown unit for bit_speed"):
        read_mat(tmp_path / "named.mat", variables={"time": ("t", "s"), "bit_speed": ("w", "hz")})


def test_record_refuses_unequal_lengths_and_empty():
    with pytest.raises(ValueError, match="bit_speed: has 3 samples"):
        Record(time_s=np.arange(4.0), bit_speed=np.ones(3))
    with pytest.raises(ValueError, match="empty"):
        Record(time_s=np.zeros(0), bit_speed=np.zeros(0))
    with pytest.raises(ValueError, match="no data channel"):
        Record(time_s=np.arange(4.0))


def test_cli_reports_bad_input_in_one_line(tmp_path, capsys):
    p = tmp_path / "only_wob.csv"
    p.write_text("time_s,wob_N\n0,1\n0.001,2\n0.002,3\n")
    assert main(["analyze", str(p), "--out", str(tmp_path / "out")]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and err[0].startswith("drillpy: error:") and "'bit_speed' is missing" in err[0]


def test_all_nan_torque_column_names_the_torque_and_the_file(tmp_path, capsys):
    r = sample175_raw().select(10, 12)
    r.torque_on_bit[:] = np.nan
    p = write_csv(r, tmp_path / "no_torque.csv")
    with pytest.raises(ValueError, match=r"no_torque.csv.*column 'torque_on_bit_Nm' \(torque_on_bit\) has no value"):
        read_record(p)
    # the command says the same, in one line, and does not blame the bit speed
    assert main(["analyze", str(p), "--out", str(tmp_path / "out"), "--no-sim"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "torque_on_bit_Nm" in err[0] and "no_torque.csv" in err[0]
    assert "bit_speed" not in err[0] and "bit-speed" not in err[0]
    savemat(tmp_path / "nan.mat", {"Time_Sample_1_complete": r.time_s, "Bit_Torque_Sample_1_complete": r.torque_on_bit,
                                   "Bit_Speed_Sample_1_complete": r.bit_speed * RPM})
    with pytest.raises(ValueError, match=r"nan.mat.*'Bit_Torque_Sample_1_complete' \(torque_on_bit\) has no finite"):
        read_mat(tmp_path / "nan.mat")


def test_csv_rows_out_of_time_order_are_sorted_not_restamped(tmp_path):
    r = sample175_raw().select(10, 11)
    p = write_csv(r, tmp_path / "s.csv")
    lines = p.read_text().splitlines()
    h = next(i for i, ln in enumerate(lines) if ln.startswith("time_s"))
    lines[h + 301], lines[h + 302] = lines[h + 302], lines[h + 301]  # two rows swapped in the file
    p.write_text("\n".join(lines) + "\n")
    back = read_record(p)
    assert back.time_s[300] > back.time_s[301]  # read as written ...
    from drillpy.records.cleaning import clean
    rec, rep = clean(back)                     # ... and sorted by time, with the values, when cleaned
    np.testing.assert_allclose(rec.bit_speed, r.bit_speed, rtol=1e-15)
    np.testing.assert_allclose(rec.time_s, r.time_s, atol=1e-9)
    (o,) = [a for a in rep.artifacts if a.kind == "order"]
    assert o.samples == 2 and o.start_s == pytest.approx(r.time_s[300])


def test_binary_or_nul_file_read_as_csv_names_the_file(tmp_path):
    """Found by test_fuzz.py: a binary file raised UnicodeDecodeError naming no file (and a cell over
    the csv module's size limit a csv.Error)."""
    p = tmp_path / "rec.csv"
    p.write_bytes(b"\x80\x01binary")
    with pytest.raises(ValueError, match=r"rec.csv': not a UTF-8 text file \(byte 0: invalid start byte\)"):
        read_record(p)
    p.write_text("time_s,wob_N\n0," + "1" * 200_000 + "\n")
    with pytest.raises(ValueError, match=r"rec.csv': not a CSV text file \(field larger than field limit"):
        read_record(p)

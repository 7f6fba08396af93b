"""Cleaning: the artifacts of sample 175 and injected faults of every kind."""
import numpy as np
import pytest

from _testrig import sample175_cleaned, sample175_raw
from drillpy.records.cleaning import CleaningOptions, clean
from drillpy.records.io import RPM, Flag, Record


def test_sample175_artifacts_found_and_repaired():
    rec, rep = sample175_cleaned()
    c = rep.counts()
    # README: isolated spikes to about -200 RPM and one stretch (28-30 s) oscillating while the bit sticks
    assert c["spike"]["events"] == 16 and c["spike"]["excluded_samples"] == 0
    assert c["oscillation"]["events"] == 1
    (osc,) = [a for a in rep.artifacts if a.kind == "oscillation"]
    assert osc.channel == "top_speed" and 28.0 < osc.start_s < osc.end_s < 29.6
    assert all(a.channel == "top_speed" for a in rep.artifacts)  # bit speed, torque, WOB are clean
    for k in ("time", "gap", "nonfinite", "duplicate"):
        assert c[k]["events"] == 0
    raw = sample175_raw()
    assert np.min(raw.top_speed) * RPM < -200 and np.min(rec.top_speed) * RPM > -10
    # the stretch is replaced by the (stuck) bit speed; other channels are untouched
    m = (rec.time_s >= osc.start_s) & (rec.time_s <= osc.end_s)
    np.testing.assert_array_equal(rec.top_speed[m], rec.bit_speed[m])
    assert np.all(np.abs(rec.bit_speed[m]) * RPM < 4.1)
    for ch in ("bit_speed", "torque_on_bit", "wob"):
        np.testing.assert_array_equal(getattr(rec, ch), getattr(raw, ch))
    # no net winding of the bar: over the record the cleaned top speed averages the bit speed
    assert np.mean(rec.top_speed) == pytest.approx(np.mean(rec.bit_speed), rel=0.03)
    assert rec.valid().all() and len(rec) == len(raw)
    assert rec.provenance["cleaning"]["counts"]["spike"]["events"] == 16


def test_cleaning_is_idempotent():
    rec, _ = sample175_cleaned()
    again, rep = clean(rec.take(np.arange(len(rec))))
    assert rep.lines() == ["no artifact found"]
    np.testing.assert_array_equal(again.top_speed, rec.top_speed)


@pytest.fixture
def window():
    """5-9 s of sample 175, without artifacts there except two top-speed spikes."""
    return sample175_raw().select(7.5, 11.5)


def test_short_nonfinite_run_is_interpolated(window):
    ref = window.torque_on_bit.copy()
    window.torque_on_bit[1000:1010] = np.nan
    window.wob[2000] = np.inf
    rec, rep = clean(window)
    fl = rec.flags["torque_on_bit"][1000:1010]
    assert np.all(fl & Flag.NONFINITE) and np.all(fl & Flag.REPAIRED)
    assert np.max(np.abs(rec.torque_on_bit[1000:1010] - ref[1000:1010])) < 0.05  # N m, 10 ms of a 10 Hz signal
    assert rep.counts()["nonfinite"] == {"events": 2, "samples": 11, "repaired_samples": 11, "excluded_samples": 0}
    assert rec.valid().all()


def test_long_nonfinite_run_is_excluded_not_invented(window):
    window.bit_speed[1000:1200] = np.nan
    rec, rep = clean(window)
    assert np.all(np.isnan(rec.bit_speed[1000:1200]))
    assert np.all(rec.flags["bit_speed"][1000:1200] & Flag.UNRELIABLE)
    assert (~rec.valid()).sum() == 200 and rep.counts()["nonfinite"]["excluded_samples"] == 200


def test_gaps_are_refilled_on_the_grid(window):
    n = len(window)
    keep = np.ones(n, bool)
    keep[500:520] = False      # 20 ms: interpolated
    keep[2000:2300] = False    # 300 ms: inserted but excluded
    rec, rep = clean(window.take(np.flatnonzero(keep)))
    assert len(rec) == n
    np.testing.assert_allclose(rec.time_s, window.time_s, atol=1e-9)
    gaps = [a for a in rep.artifacts if a.kind == "gap"]
    assert [(g.samples, g.repaired) for g in gaps] == [(20, True), (300, False)]
    assert np.all(rec.flags["time"][500:520] & Flag.GAP)
    assert np.all(np.isfinite(rec.wob[500:520])) and np.all(np.isnan(rec.wob[2000:2300]))
    assert (~rec.valid()).sum() == 300


def test_backward_time_stamp_and_duplicate_row(window):
    t = window.time_s.copy()
    t[1500] -= 0.5                         # a stamp that jumps back onto another row's slot
    window.time_s = t
    idx = np.r_[np.arange(3000), 2999, np.arange(3000, len(window))]  # one row logged twice
    rec, rep = clean(window.take(idx))
    c = rep.counts()
    assert c["duplicate"]["events"] == 1 and c["time"]["events"] == 1 and c["order"]["events"] == 0
    assert len(rec) == len(window)
    np.testing.assert_allclose(np.diff(rec.time_s), 1e-3, rtol=1e-9)
    assert rec.flags["time"][1500] & Flag.TIME
    np.testing.assert_array_equal(rec.bit_speed, window.bit_speed)  # re-stamped in acquisition order


@pytest.mark.parametrize("pairs", [[(2500, 2501)], [(10, 11), (3000, 3001)]])
def test_swapped_rows_are_sorted_by_time_and_reported(window, pairs):
    idx = np.arange(len(window))
    for a, b in pairs:                     # whole rows (stamp and values) logged out of order
        idx[a], idx[b] = idx[b], idx[a]
    swapped = window.take(idx)
    assert np.any(np.diff(swapped.time_s) < 0)
    rec, rep = clean(swapped)
    np.testing.assert_allclose(rec.time_s, window.time_s, rtol=0, atol=1e-9)  # the uniform grid
    for ch in window.channels:  # back in time order, every channel with its stamp
        np.testing.assert_array_equal(getattr(rec, ch), getattr(window, ch))
    order = [a for a in rep.artifacts if a.kind == "order"]
    assert [o.samples for o in order] == [b - a + 1 for a, b in pairs]
    assert rep.counts()["time"]["events"] == 0 and rep.counts()["order"]["events"] == len(pairs)
    a, b = pairs[-1]
    assert order[-1].start_s == pytest.approx(window.time_s[a]) and "sorted by time stamp" in order[-1].repair
    assert any("out of time order" in n for n in rep.notes)  # never silently
    assert np.all(rec.flags["time"][a:b + 1] & Flag.TIME) and not (rec.flags["time"][b + 1] & Flag.TIME)
    assert rec.provenance["cleaning"]["counts"]["order"]["samples"] == sum(b - a + 1 for a, b in pairs)


def test_all_nan_channel_is_an_error_naming_it(window):
    window.torque_on_bit[:] = np.nan
    with pytest.raises(ValueError, match="channel 'torque_on_bit'.*no finite value") as e:
        clean(window)
    assert "sample175" in str(e.value) and "bit_speed" not in str(e.value)


def test_overlapping_pieces_cannot_be_placed(window):
    t = window.time_s.copy()
    t[2000:] -= 1.0  # a second piece that starts 1 s back in time
    window.time_s = t
    with pytest.raises(ValueError, match="cannot be placed"):
        clean(window)


def test_injected_spike_in_bit_speed_is_repaired(window):
    ref = window.bit_speed.copy()
    window.bit_speed[1500:1508] += 150 / RPM
    rec, rep = clean(window)
    spikes = [a for a in rep.artifacts if a.kind == "spike" and a.channel == "bit_speed"]
    assert len(spikes) == 1 and spikes[0].repaired
    assert np.max(np.abs(rec.bit_speed - ref)) * RPM < 10


def test_oscillation_while_the_bit_moves_is_excluded(window):
    # spikes every 40 ms in the top speed while the bit slips (8-9 s): not repairable
    for k in range(10):
        a = 600 + 40 * k
        window.top_speed[a:a + 8] = -200 / RPM
    rec, rep = clean(window, CleaningOptions(stuck_fraction=0.9))
    (osc,) = [a for a in rep.artifacts if a.kind == "oscillation"]
    assert not osc.repaired and "UNRELIABLE" in osc.repair
    m = (rec.time_s >= osc.start_s) & (rec.time_s <= osc.end_s)
    assert not rec.valid("top_speed")[m].any() and rec.valid("bit_speed")[m].all()


def test_held_values_are_flagged_in_every_channel(window):
    # a frozen bit encoder in slip, a torque channel dropped out to 0, a WOB load cell saturated
    ref = {ch: getattr(window, ch).copy() for ch in ("bit_speed", "torque_on_bit", "wob")}
    slipping = int(np.flatnonzero(window.bit_speed > 60 / RPM)[0])
    window.bit_speed[slipping:slipping + 300] = window.bit_speed[slipping]
    window.torque_on_bit[2000:2200] = 0.0
    window.wob[3000:3500] = 2000.0
    rec, rep = clean(window)
    flats = {a.channel: a for a in rep.artifacts if a.kind == "flatline"}
    assert set(flats) == {"bit_speed", "torque_on_bit", "wob"}
    assert [flats[ch].samples for ch in ("bit_speed", "torque_on_bit", "wob")] == [300, 200, 500]
    assert all(not a.repaired for a in flats.values()) and "2000 held for 500 samples" in flats["wob"].repair
    for ch, sl in (("bit_speed", slice(slipping, slipping + 300)), ("torque_on_bit", slice(2000, 2200)),
                   ("wob", slice(3000, 3500))):
        assert np.all(rec.flags[ch][sl] & Flag.FLATLINE) and not rec.valid(ch)[sl].any()
        keep = np.ones(len(rec), bool)
        keep[sl] = False
        assert rec.valid(ch)[keep].all()
        np.testing.assert_array_equal(getattr(rec, ch)[keep], ref[ch][keep])
    # the WOB's spread without the saturated stretch is the clean record's (within the held half second)
    assert np.std(rec.wob[rec.valid("wob")]) == pytest.approx(np.std(ref["wob"]), rel=0.05)
    assert rep.counts()["flatline"] == {"events": 3, "samples": 1000, "repaired_samples": 0,
                                        "excluded_samples": 1000}


def test_a_stuck_bit_a_set_point_and_a_quantized_channel_are_not_held_values(window):
    n = len(window)
    window.bit_speed[1000:1400] = 0.0            # a noise-free stuck bit ...
    window.torque_on_bit[1000:1400] = 3.0        # ... holding the torque of a stalled drive
    window.top_speed[:] = 160 / RPM              # an ideal drive's set point
    window.wob = np.round(window.wob / 20.0) * 20.0  # a load cell read in 20 N steps
    rec, rep = clean(window)
    assert rep.counts()["flatline"]["events"] == 0
    assert not any(rec.flagged(ch, Flag.FLATLINE).any() for ch in ("bit_speed", "top_speed", "wob", "torque_on_bit"))
    # the 20 N steps do hold for more than 0.1 s: only the quantization test keeps them as motion
    _, rep = clean(window, CleaningOptions(flatline_quantized_fraction=1.0))
    assert [a.channel for a in rep.artifacts if a.kind == "flatline"] == ["wob"]
    window.bit_speed[1000:1400] = 0.0
    rec, rep = clean(window, CleaningOptions(flatline_min_s=0.0))  # the search switched off
    assert rep.counts()["flatline"]["events"] == 0 and len(rec) == n


def test_bad_options_are_refused():
    with pytest.raises(ValueError, match="cleaning.max_fill_s"):
        CleaningOptions(max_fill_s=-1).validate()
    with pytest.raises(ValueError, match="cleaning.flatline_min_s"):
        CleaningOptions(flatline_min_s=-0.1).validate()
    with pytest.raises(ValueError, match="stretch_min_spikes"):
        CleaningOptions(stretch_min_spikes=1).validate()
    with pytest.raises(ValueError, match="only 2 finite time stamp"):
        clean(Record(time_s=np.array([0.0, 1.0, np.nan]), wob=np.ones(3)))


def test_time_errors_name_the_file_and_far_off_stamps_are_refused_fast(tmp_path):
    """Found by test_fuzz.py: time-stamp errors named no file; a stamp far off the others asked for a
    grid of 10^15 samples, and a nanosecond step made the spike search take seconds on six rows."""
    import time
    from drillpy.records.io import read_record
    p = tmp_path / "r.csv"
    p.write_text("time_s,wob_N\n0,1\n1,2\n")
    with pytest.raises(ValueError, match=r"record = '.*r.csv': time_s: only 2 finite time stamp"):
        clean(read_record(p))
    t = np.arange(1000) * 1e-3
    t[-1] = 1e12  # one stamp far off: refused, not a grid of 10^15 samples
    with pytest.raises(ValueError, match=r"time_s: the time stamps span 0 to 1e\+12 s"):
        clean(Record(time_s=t, wob=np.ones(t.size)))
    start = time.perf_counter()
    rec, rep = clean(Record(time_s=np.arange(6) * 1e-9, torque_on_bit=np.array([1.0, 2, 3, 50, 4, 5])))
    assert time.perf_counter() - start < 1.0 and len(rec) == 6 and rep.dt_s == pytest.approx(1e-9)


def test_stamps_out_of_order_throughout_are_refused_not_an_index_error():
    """Found by test_fuzz.py: re-stamping the neighbours of bad stamps could swallow every anchor and
    raise IndexError; such a record is refused with the rows named."""
    t = np.array([0.001, 0.0, 0.002, 0.003, 0.004, 0.005, 0.009, 0.007, 0.014, 0.006, 0.01, 0.012, 0.011, 0.013,
                  0.008, 0.015, 0.016, 0.017, 0.018])
    x = 50 + np.arange(t.size, dtype=float)
    x[3] = np.nan
    with pytest.raises(ValueError, match=r"time_s: 18 sample\(s\) from row 0 .* to row 17 cannot be placed"):
        clean(Record(time_s=t, bit_speed=x))

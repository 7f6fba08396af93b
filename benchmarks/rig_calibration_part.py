"""What the rig calibration of ``drillpy analyze`` starts from, for its benchmarks: a record's
calibration part (0-20 s, cleaned), its stick threshold and the Eq. (5.1) law identified on it."""
from __future__ import annotations

from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[1]
SAMPLE175 = REPO.parent / "shared" / "data" / "testrig" / "sample175_0-40s.mat"


def calibration_part(path: str = str(SAMPLE175)) -> tuple:
    """(record 0-20 s cleaned, stick threshold [rad/s], Eq. 5.1 law) of the record at ``path``."""
    from drillpy.records import identification as ident
    from drillpy.records import rigsim
    from drillpy.records import signals as sig
    from drillpy.records.cleaning import clean
    from drillpy.records.io import read_mat
    rec = clean(read_mat(path))[0].select(0.0, 20.0)
    thr = 0.05 * float(np.median(rec.top_speed[rigsim.reliable_top_speed(rec)]))
    cyc = sig.segment_cycles(rec.bit_speed, rec.dt, thr, valid=rec.valid())
    d = ident.FitData.from_arrays(rec.bit_speed, sig.derivative(rec.bit_speed, rec.dt), rec.torque_on_bit,
                                  cyc.branch_labels(len(rec)), cyc.cycle_id(len(rec)), wob=rec.wob, every=10,
                                  cycles=cyc)
    return rec, thr, ident.fit_law("polynomial", d).law

"""Options of ``drillpy loop`` (:class:`LoopOptions`)."""
from __future__ import annotations

import math
from dataclasses import dataclass

from .effects import NAMES


@dataclass
class LoopOptions:
    """Choices of :func:`run_loop`.

    Attributes
    ----------
    horizon_s : float
        Length of the prediction horizons; the model is restarted from the measured state at the
        start of each [s].
    calibration_fraction : float
        Fraction of the record (from its start) used to calibrate; the rest validates.
    rate_hz : float
        Analysis sampling rate [Hz] (the record is decimated by an integer factor to at most this).
    derivative_window_s : float
        Width of the Savitzky-Golay filters (polynomial order 4) that give the channels'
        derivatives and smoothed values [s].
    min_gain : float
        Minimum relative improvement of the validation error for an effect to be added.
    alpha : float
        Family-wise level of the one-sided paired test per round (divided by the number of
        candidates of the round: Bonferroni).
    min_delta_bic : float
        Minimum BIC improvement on the calibration part (6: "strong" on the Kass-Raftery scale).
    max_steps : int
        At most this many effects are added.
    effects : tuple
        Candidate effects (default: the whole catalogue).
    stick_fraction : float
        The bit is stuck at or below this fraction of the median top speed.
    threads : int
        Engine threads (0: OpenMP default).
    dt_s : float, optional
        Engine time step of the predictions [s] (default: the declared configuration's); it is
        lowered, if needed, to divide the analysis sampling interval.
    nfev_per_parameter : int
        Optimizer budget: at most this many evaluations per fitted parameter, the same for the
        baseline, the null candidate and every candidate.
    backward : bool
        After each addition (and on the declared model), try to remove every other effect; an effect
        whose removal the guard does not refuse is removed.
    long_run : bool
        Simulate every corrected model over the record at its operating point and compare SS, stick
        fraction and cycle frequency with the record's; a correction that destroys a measured
        stick-slip cycle is rejected.
    discovery : bool
        Regress the final model's residual on a library of candidate terms (sparse regression).
    """
    horizon_s: float = 0.25
    calibration_fraction: float = 0.5
    rate_hz: float = 1000.0
    derivative_window_s: float = 0.031
    min_gain: float = 0.05
    alpha: float = 0.05
    min_delta_bic: float = 6.0
    max_steps: int = 6
    effects: tuple = NAMES
    stick_fraction: float = 0.05
    threads: int = 0
    dt_s: float | None = None
    nfev_per_parameter: int = 60
    backward: bool = True
    long_run: bool = True
    discovery: bool = True

    def validate(self) -> None:
        def pos(name, v, lo=0.0, hi=math.inf, closed=False):
            ok = isinstance(v, (int, float)) and math.isfinite(v) and (lo <= v if closed else lo < v) and v < hi
            if not ok:
                raise ValueError(f"{name} = {v!r}: must be a number in {'[' if closed else '('}{lo:g}, {hi:g})")
        pos("horizon_s", self.horizon_s)
        pos("calibration_fraction", self.calibration_fraction, 0.0, 1.0)
        pos("rate_hz", self.rate_hz)
        pos("derivative_window_s", self.derivative_window_s)
        pos("min_gain", self.min_gain, 0.0, 1.0, closed=True)
        pos("alpha", self.alpha, 0.0, 1.0)
        pos("min_delta_bic", self.min_delta_bic, -math.inf)
        pos("stick_fraction", self.stick_fraction, 0.0, 1.0)
        if self.dt_s is not None:
            pos("dt_s", self.dt_s)
        if not isinstance(self.nfev_per_parameter, int) or self.nfev_per_parameter < 1:
            raise ValueError(f"nfev_per_parameter = {self.nfev_per_parameter!r}: must be a positive integer")
        if not isinstance(self.max_steps, int) or self.max_steps < 0:
            raise ValueError(f"max_steps = {self.max_steps!r}: must be a non-negative integer")
        for e in self.effects:
            if e not in NAMES:
                raise ValueError(f"effects: unknown effect {e!r} (known: {', '.join(NAMES)})")


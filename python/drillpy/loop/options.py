"""Options of ``drillpy loop`` (:class:`LoopOptions`)."""
from __future__ import annotations

from dataclasses import dataclass

from .effects import NAMES
from .effects.string_stiffness import MARGIN as GJ_TOLERANCE
from drillpy import validate
from drillpy.records.stick import STICK_FRACTION

#: Largest RMS difference of the horizon predictions, in units of E's spreads, a coarser engine step may
#: make (:mod:`drillpy.loop.time_step`).
STEP_TOLERANCE = 0.0035

#: Values of :attr:`LoopOptions.wob_input`.
WOB_INPUTS = ("auto", "measured", "trend")
#: The bit-rock torque of the long runs: the record's fluctuation of Eq. (4.1), or the law alone.
LONG_RUN_FLUCTUATIONS = ("record", "none")


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
        Engine time step of the predictions [s], lowered if needed to divide the analysis sampling
        interval. Default: the step rule (``step_tolerance``) from the declared configuration's step.
    step_tolerance : float
        The step rule (:mod:`drillpy.loop.time_step`; without ``dt_s``): the loop predicts at the
        coarsest step, at least twice the declared one and dividing the analysis interval, whose
        horizon predictions differ from the declared step's by at most this RMS fraction of E's
        spreads, which bounds the change of any E it reports by the same amount; measured on the
        declared model, confirmed on the calibrated baseline (else the declared step) and reported
        for the final model (``loop.json`` -> ``time_step``). Default 0.0035: sample 175 runs at
        2.5e-4 s instead of 1e-4 s with the same decisions, the Stribeck rig's record at its
        declared 1e-4 s (docs/loop.md, "The engine step"). 0: the declared step. A coarser step
        alone is not enough: the calibration's least squares can end in another local minimum and
        a decision near the gate can flip (``benchmarks/loop_timestep.py``).
    scheme : str
        The engine's scheme for every prediction: ``"modified_euler"`` (default: appendix A, the
        thesis's) or ``"exact_modal"`` (issue 33: each mode's linear part exact over the step, the
        motor and the jack stepped as in the modified Euler). With ``exact_modal`` at 1 ms the
        calibration follows the step far less: on sample 175 the baseline and the decisions are the
        modified Euler's at 1e-4 s, about 3 x faster; on the Stribeck rig's record its answer at
        1 ms is its own at 1e-4 s (``benchmarks/loop_timestep.py --scheme exact_modal``, docs/loop.md).
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
    batched : bool
        Step the short horizons in SIMD lockstep (the batched integrator, default) instead of the
        scalar reference integrator. The predictions differ by rounding (about 1e-14 rad/s), which
        is enough to change a decision that sits at a threshold; on sample 175 both paths give the
        same answer, the batched one 2.3 x faster (``benchmarks/loop_sample175.py``); the
        validation tables of docs/loop.md are run on it.
    batched_jacobian : bool
        Evaluate the perturbed models of each finite-difference Jacobian of the calibration in one
        engine call (``_core.predict_horizons_many``, default) instead of one call each (scipy's own
        '2-point' differences, False). The steps are scipy's and the engine's lanes are bit-identical
        to single runs, so both give the same Jacobian bit for bit and the same calibration
        (``benchmarks/bench_loop.py`` times both; docs/loop.md, "Calibration").
    blas_threads : int
        BLAS threads of the optimizer's linear algebra while the loop runs (1; 0: the library's
        default). One is fastest: OpenBLAS's threads gain nothing on the tall Jacobians' SVDs and
        spin after each call, taking the cores from the engine's OpenMP threads (sample 175:
        ``benchmarks/loop_sample175.py``); with one the answer cannot depend on the BLAS thread
        count either.
    law_knot : bool
        Calibrate, with the rest of a polynomial law (Eq. 5.1/5.3), where its low-speed linear piece
        meets the cubic (the knot v_k, RPM, 4-60) and the torque at the piece's lower end (v_k / 5):
        the law's own low-speed shape, which the thesis ties to 1 % and 5 % of the mean bit speed.
        A law that rises after the break-away (Tucker-Wang's, Eq. 3.1) then needs no effect to
        stand in for it (docs/loop.md). False keeps the thesis's tie.
    wob_input : str
        The WOB the law takes: ``"auto"`` (default) decides from the record
        (:func:`drillpy.loop.data.wob_response`): the recorded WOB where it is an input of the
        torsional dynamics, its slow trend below 0.5 Hz where its fast part is a response of them
        (the test rig's jack: the recorded WOB carries the stick-slip cycle, and a model fed it would
        be given the answer it should predict); ``"measured"`` or ``"trend"`` force one.
    gj_tolerance : float
        Relative tolerance of the declared string GJ (0.03: a bar radius known to +-0.75 %, the
        ``string_stiffness`` margin): the GJ is calibrated within 1 +- it like the damping (a value
        the declared model leaves uncertain); a mismatch beyond it is ``string_stiffness``, found
        with evidence. 0 holds the declared GJ.
    channel_timing : str or tuple
        The channels' timing (:func:`drillpy.records.bit_balance.aligned`): ``"auto"`` (default: the
        timing that balances the bit's equation, the string's stiffness and inertia fitted, on the
        calibration part, :func:`drillpy.records.bit_balance.identify_timing`, where the record
        identifies a skew; a record without one, or without top speed, is left as recorded),
        ``"none"`` (as recorded) or (top lead, torque lag) [s]. The record's channels are
        brought to the bit encoder's time before anything else (docs/loop.md, "The channels'
        timing"); the model file keeps the timing and ``drillpy predict`` reads the records it
        scores at it.
    long_run_fluctuation : str
        The bit-rock torque of the long runs (:func:`drillpy.loop.longrun.simulate_record`):
        ``"none"`` (default) runs the law alone (deterministic); ``"record"`` carries the fluctuation
        of Eq. (4.1) the calibration part shows (eta_exp of Eq. 4.2, its Eq. 4.4 PSD and standard
        deviation: :func:`drillpy.records.rig_fluctuation.of_record`), one realization of seed 0. The
        short-horizon predictions are the law's in both (docs/loop.md, "The long run's torque
        fluctuation").
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
    stick_fraction: float = STICK_FRACTION
    threads: int = 0
    dt_s: float | None = None
    step_tolerance: float = STEP_TOLERANCE
    scheme: str = "modified_euler"
    nfev_per_parameter: int = 60
    backward: bool = True
    long_run: bool = True
    discovery: bool = True
    batched: bool = True
    batched_jacobian: bool = True
    blas_threads: int = 1
    law_knot: bool = True
    gj_tolerance: float = GJ_TOLERANCE
    wob_input: str = "auto"
    channel_timing: str | tuple = "auto"
    long_run_fluctuation: str = "none"

    def validate(self) -> None:
        """Check every option (ranges, types, known effect names).

        Raises
        ------
        ValueError
            On the first option out of its range (e.g. ``horizon_s`` <= 0 s, ``calibration_fraction``
            outside (0, 1), ``min_gain`` outside [0, 1), ``nfev_per_parameter`` < 1) or an unknown
            effect in ``effects``.
        """
        validate.positive("horizon_s", self.horizon_s, "s")
        validate.fraction("calibration_fraction", self.calibration_fraction, closed=False)
        validate.positive("rate_hz", self.rate_hz, "Hz")
        validate.positive("derivative_window_s", self.derivative_window_s, "s")
        validate.number("min_gain", self.min_gain, lo=0.0, hi=1.0, hi_closed=False)
        validate.fraction("alpha", self.alpha, closed=False)
        validate.number("min_delta_bic", self.min_delta_bic)
        validate.fraction("stick_fraction", self.stick_fraction, closed=False)
        if self.dt_s is not None:
            validate.positive("dt_s", self.dt_s, "s")
        validate.number("step_tolerance", self.step_tolerance, lo=0.0, hi=0.1)
        if self.scheme not in ("modified_euler", "exact_modal"):
            raise ValueError(f"scheme = {self.scheme!r}: the loop runs 'modified_euler' or 'exact_modal'")
        validate.integer("nfev_per_parameter", self.nfev_per_parameter, 1)
        validate.number("gj_tolerance", self.gj_tolerance, lo=0.0, hi=0.5, hi_closed=False)
        validate.integer("max_steps", self.max_steps, 0)
        validate.integer("blas_threads", self.blas_threads, 0)
        if isinstance(self.channel_timing, str):
            if self.channel_timing not in ("none", "auto"):
                raise ValueError(f"channel_timing = {self.channel_timing!r}: use 'none', 'auto' or (top lead, torque "
                                 "lag) in s")
        elif len(tuple(self.channel_timing)) != 2:
            raise ValueError(f"channel_timing = {self.channel_timing!r}: use 'none', 'auto' or (top lead, torque lag) "
                             "in s")
        else:
            for name, x in zip(("channel_timing[0] (top lead)", "channel_timing[1] (torque lag)"), self.channel_timing):
                validate.number(name, x, lo=-0.2, hi=0.2)
        if self.long_run_fluctuation not in LONG_RUN_FLUCTUATIONS:
            raise ValueError(f"long_run_fluctuation = {self.long_run_fluctuation!r}: use one of "
                             f"{', '.join(LONG_RUN_FLUCTUATIONS)}")
        if self.wob_input not in WOB_INPUTS:
            raise ValueError(f"wob_input = {self.wob_input!r}: use one of {', '.join(WOB_INPUTS)}")
        for e in self.effects:
            if e not in NAMES:
                raise ValueError(f"effects: unknown effect {e!r} (known: {', '.join(NAMES)})")


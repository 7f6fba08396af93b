"""
drillpy engine: FE/ROM torsional drill-string model, bit-rock laws, integrators
"""
from __future__ import annotations
import collections.abc
import numpy
import numpy.typing
import typing
__all__: list[str] = ['AxialReport', 'Config', 'FrfEnvelope', 'HorizonResult', 'HorizonStart', 'MonteCarlo', 'RunReport', 'SeverityStatistics', 'Simulation', 'StochasticModel', 'cb_frequencies', 'conv1', 'craig_bampton', 'exact_frequencies', 'fe_matrices', 'generate_process', 'law_torque', 'lowpass2', 'max_dispersion', 'max_threads', 'natural_frequencies', 'normalize_config', 'observation_nodes', 'predict_horizons', 'predict_horizons_many', 'preset_json', 'preset_names', 'process_grid', 'process_variance', 'psd_model_integral', 'psd_model_values', 'psd_table_values', 'random_matrix', 'run_many', 'severity_statistics', 'severity_threshold', 'state_from_bit', 'thesis_case_dispersions', 'top_torque_from_bit', 'with_total_elements']
class Config:
    """
    A validated engine configuration (the JSON schema drillsim reads), parsed once. Pass it to Simulation, StochasticModel, MonteCarlo and the model functions (built from a dict by drillpy.model.config.engine_config).
    """
    @staticmethod
    def from_dict(config: dict) -> Config:
        """
        Parse and validate a configuration given as a dict, without JSON text: the same Config as Config(json.dumps(config)) (ValueError naming the field when invalid). No plausibility warnings (drillpy.model.config.engine_config gives those): for a program's configurations, e.g. the trials of drillpy loop's calibration.
        """
    def __init__(self, json: str) -> None:
        """
        Parse and validate a JSON configuration (ValueError naming the field when invalid).
        """
    def __repr__(self) -> str:
        ...
    def to_dict(self) -> dict:
        """
        The configuration as a dict with every default made explicit (the normalized form).
        """
    def to_json(self) -> str:
        """
        JSON text of the configuration with every default made explicit.
        """
    @property
    def dt_s(self) -> float:
        """
        Integration time step [s].
        """
    @property
    def duration_s(self) -> float:
        """
        Simulated duration [s].
        """
    @property
    def modes(self) -> int:
        """
        Number of retained modes of the reduced model (rom.modes).
        """
    @property
    def name(self) -> str:
        """
        Name of the configuration (config.name).
        """
    @property
    def start(self) -> str:
        """
        Initial state of runs and sweeps (simulation.start): rest, rigid or steady.
        """
    @property
    def top_speed_rad_s(self) -> float:
        """
        Top speed of the operating point [rad/s].
        """
    @property
    def transient_s(self) -> float:
        """
        Transient discarded before the metrics [s].
        """
    @property
    def wob_n(self) -> float:
        """
        Weight on bit of the operating point [N].
        """
class AxialReport:
    """
    Axial channels and metrics of a run of the axial-torsional model (axial.type = rgd, drill/axial_torsional.hpp): series every simulation.output_stride steps, metrics over t >= transient. Empty (present False) for other models.
    """
    @property
    def bounce_fraction(self) -> float:
        """
        Fraction of the time after the transient with the bit off the rock (W = 0), dimensionless.
        """
    @property
    def delay(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        The delay t_N of Phi(t) - Phi(t - t_N) = 2 pi / N [s].
        """
    @property
    def depth_of_cut(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Depth of cut per revolution d = N [U(t) - U(t - t_N)] [m] (negative: the bit above the rock).
        """
    @property
    def mean_depth_of_cut(self) -> float:
        """
        Mean depth of cut per revolution [m].
        """
    @property
    def mean_rop(self) -> float:
        """
        Mean rate of penetration after the transient [m/s].
        """
    @property
    def mean_wob(self) -> float:
        """
        Mean WOB after the transient [N].
        """
    @property
    def mse(self) -> float:
        """
        Mechanical specific energy after the transient: the bit's work on the rock per volume removed (torque x bit speed + WOB x axial speed, over pi a^2 x advance) [Pa]; NaN without advance.
        """
    @property
    def position(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        The bit's axial position U [m] (down positive).
        """
    @property
    def present(self) -> bool:
        """
        True for a run of the axial-torsional model.
        """
    @property
    def rop(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        The bit's axial speed V [m/s] (positive into the rock).
        """
    @property
    def rop_std(self) -> float:
        """
        Standard deviation of the bit's axial speed [m/s].
        """
    @property
    def steady_depth(self) -> float:
        """
        Depth of cut per revolution of steady drilling [m].
        """
    @property
    def steady_mse(self) -> float:
        """
        MSE of steady drilling, W / A + T Omega / (A V) (Teale 1965) [Pa].
        """
    @property
    def steady_rop(self) -> float:
        """
        Rate of penetration of steady drilling [m/s].
        """
    @property
    def steady_speed(self) -> float:
        """
        Speed of steady drilling under the top drive [rad/s]: the command, or a drooping drive's (the motor's); NaN where the drive cannot carry steady drilling (it stalls; the run starts from the command's steady drilling).
        """
    @property
    def steady_torque(self) -> float:
        """
        Torque on bit of steady drilling [N m].
        """
    @property
    def steady_wob(self) -> float:
        """
        WOB of RGD's steady drilling at the operating point [N].
        """
    @property
    def t(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Sample times [s].
        """
    @property
    def wob(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Weight on bit W = W_c + W_f of the RGD law [N] (0 off the rock).
        """
    @property
    def wob_std(self) -> float:
        """
        Standard deviation of the WOB after the transient [N].
        """
class RunReport:
    """
    Time series (SI, absolute frame) and metrics of one run (Simulation.run). The series are sampled every simulation.output_stride steps and are empty with record=False.
    """
    def summary(self) -> dict:
        """
        The run's summary (drill/run_summary.hpp, the summary.json of drillsim and drillpy simulate without config and job): severity, mean_top_speed_rad_s, stick_fraction, stick_durations_s, slip_durations_s, period_cycles, period_stick_s, period_slip_s; undefined values are None.
        """
    def to_dict(self) -> dict:
        """
        Every field in a dict keyed by the field names (t, bit_speed, ..., final_q, final_qdot).
        """
    @property
    def axial(self) -> AxialReport:
        """
        Axial channels and metrics (AxialReport) of an axial-torsional run; present is False otherwise.
        """
    @property
    def bit_accel(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Bit acceleration [rad/s^2].
        """
    @property
    def bit_angle(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Bit angle [rad].
        """
    @property
    def bit_speed(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Bit speed [rad/s].
        """
    @property
    def final_q(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Reduced coordinates q at the end of the run (Eq. 2.8; modal amplitudes of the rotation relative to the top [rad]).
        """
    @property
    def final_qdot(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Their time derivative q' at the end of the run [1/s].
        """
    @property
    def mean_top_speed(self) -> float:
        """
        Mean top speed over t >= transient [rad/s].
        """
    @property
    def period_cycles(self) -> int:
        """
        Stick-slip cycles after which the phase durations repeat (0: no periodic regime).
        """
    @property
    def period_mismatch(self) -> float:
        """
        Largest difference between durations one period apart [s].
        """
    @property
    def period_slip(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Slip durations of the last period [s].
        """
    @property
    def period_stick(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Stick durations of the last period [s].
        """
    @property
    def severity(self) -> float:
        """
        Stick-slip severity SS over t >= transient, Eq. (3.4), dimensionless (NaN when undefined).
        """
    @property
    def slip_durations(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Durations of the complete slip phases after the transient [s].
        """
    @property
    def slip_first(self) -> bool:
        """
        True when the first complete phase after the transient is a slip phase.
        """
    @property
    def stick_durations(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Durations of the complete stick phases after the transient [s].
        """
    @property
    def stick_fraction(self) -> float:
        """
        Fraction of t >= transient spent in stick, dimensionless (NaN when undefined).
        """
    @property
    def t(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Sample times [s].
        """
    @property
    def top_speed(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Top speed [rad/s] (the motor's with a motor top drive).
        """
    @property
    def top_torque(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Elastic torque at the top of the string [N m].
        """
    @property
    def torque_on_bit(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Torque on bit of the bit-rock law [N m] (Eqs. 3.1-3.3; string friction left out).
        """
    @property
    def wob(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Weight on bit the law saw [N]: the input, or the axial jack's state (axial.hpp).
        """
class Simulation:
    """
    A configured reduced-order simulation (appendix B).
    """
    @staticmethod
    def batch_width() -> int:
        """
        Runs per SIMD batch of the batched integrator on this host (the lanes of a double vector).
        """
    def __init__(self, config: Config) -> None:
        ...
    def motor_stability_bound(self, inertia_kg_m2: typing.SupportsFloat | typing.SupportsIndex) -> float:
        """
        Modified-Euler bound [s] (Eq. A.7) with a motor top drive of this inertia coupled to the string.
        """
    def reduced_matrices(self) -> dict:
        """
        Generalized matrices and couplings of the reduced model (Eqs. 2.8-2.10).
        """
    def run(self, top_speed: typing.Any = None, wob: typing.Any = None, top_speed_series: typing.Any = None, wob_series: typing.Any = None, eta_series: typing.Any = None, series_dt: typing.SupportsFloat | typing.SupportsIndex = 0.001, series_t0: typing.SupportsFloat | typing.SupportsIndex = 0.0, bit_viscous: typing.Any = None, string_friction: typing.Any = None, record: bool = True, q0: typing.Any = None, qdot0: typing.Any = None, top_speed0: typing.Any = None) -> RunReport:
        """
        Run one simulation; series inputs are sampled every series_dt from series_t0; top_speed0 is the initial motor speed of a motor top drive (default: its command).
        """
    def steady_state(self, top_speed: typing.SupportsFloat | typing.SupportsIndex, wob: typing.SupportsFloat | typing.SupportsIndex, with_top_speed: bool = False) -> tuple:
        """
        Reduced state (q, q') of steady drilling at a top speed (and the top's speed, which a motor top drive lowers below its command, with with_top_speed).
        """
    def sweep(self, speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], wobs: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex] = [], progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0, start: str | None = None, batched: bool = True) -> numpy.typing.NDArray[numpy.float64]:
        """
        SS (Eq. 3.4) on a WOB x top-speed grid, in parallel; start: rest (Eq. 2.10), rigid (Eq. 2.3) or steady (default: the configuration's simulation.start); batched: runs in SIMD lockstep where the batched integrator supports them (False: one by one through the scalar reference integrator).
        """
    @property
    def config(self) -> Config:
        """
        The configuration (a copy).
        """
    @property
    def drive_gains(self) -> typing.Any:
        """
        The resolved gains of a controlled top drive (kp, ki, Z, tau, J, L; the top section's impedance and the first natural frequency they were tuned from), None for another drive.
        """
    @property
    def frequencies_hz(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Natural frequencies of the retained modes [Hz].
        """
    @property
    def stability_bound(self) -> float:
        """
        Modified-Euler bound pi / (5 omega_max) [s] (Eq. A.7).
        """
class FrfEnvelope:
    """
    Monte Carlo envelope of the acceleration FRF for a unit torque at the bit (section 6.6, StochasticModel.envelope). Matrices are n_freq x n_nodes unless stated.
    """
    def to_dict(self) -> dict:
        """
        Every field in a dict keyed by the field names.
        """
    @property
    def energy(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        n_samples x n_nodes: int_B |a_i(omega)|^2 d omega over the band (Eq. C.2) [(rad/s^2 / N m)^2 rad/s].
        """
    @property
    def freq_hz(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
        """
        Frequencies [Hz].
        """
    @property
    def lower_db(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Quantile (1 - P)/2 of the dB response [dB].
        """
    @property
    def mean_db(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Sample mean of the dB response [dB].
        """
    @property
    def nodes(self) -> list[int]:
        """
        Observed FE nodes (1 = first free node).
        """
    @property
    def nominal_db(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Acceleration FRF of the mean (deterministic) model [dB re 1 rad/s^2 per N m].
        """
    @property
    def samples(self) -> int:
        """
        Number of realizations (0 when cancelled).
        """
    @property
    def upper_db(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Quantile (1 + P)/2 of the dB response [dB].
        """
class StochasticModel:
    """
    SM_full, SM_CB1 or SM_CB2 on a configuration (chapter 6).
    """
    def __init__(self, config: Config, model: str, delta: typing.Annotated[numpy.typing.ArrayLike, numpy.float64]) -> None:
        ...
    def envelope(self, freq_hz: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], nodes: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], samples: typing.SupportsInt | typing.SupportsIndex = 2500, seed: typing.SupportsInt | typing.SupportsIndex = 1, probability: typing.SupportsFloat | typing.SupportsIndex = 0.95, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> FrfEnvelope:
        """
        Monte Carlo envelope of the acceleration FRF (dB) for a unit torque at the bit.
        """
    def envelope_from_samples(self, freq_hz: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], nodes: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], db: typing.Annotated[numpy.typing.ArrayLike, numpy.float32], energy: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], probability: typing.SupportsFloat | typing.SupportsIndex = 0.95, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> FrfEnvelope:
        """
        Envelope of the acceleration FRF from frf_samples results stacked in sample order (db (samples, n_nodes, n_freq), energy (samples, n_nodes)) and the mean model's response; progress counts frequencies.
        """
    def frf_db(self, freq_hz: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], nodes: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], sample: typing.Any = None, seed: typing.SupportsInt | typing.SupportsIndex = 1) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Acceleration FRF [dB] of the mean model or of one realization (n_freq x n_nodes).
        """
    def frf_samples(self, freq_hz: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], nodes: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], first_sample: typing.SupportsInt | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex = 1, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[numpy.typing.NDArray[numpy.float32], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        Per-sample acceleration FRF of samples first_sample .. first_sample + samples - 1 (row r: sample first_sample + r): (db, energy) with db float32 (samples, n_nodes, n_freq) [dB] and energy (samples, n_nodes), int_B |a|^2 d omega (Eq. C.2).
        """
    def sample_matrices(self, seed: typing.SupportsInt | typing.SupportsIndex, sample: typing.SupportsInt | typing.SupportsIndex) -> dict:
        """
        Realization `sample` of the random M, D, K.
        """
    def severity_samples(self, speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], samples: typing.SupportsInt | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex = 1, structural: bool = True, eta: typing.Any = None, eta_psd: typing.Any = None, eta_dt: typing.SupportsFloat | typing.SupportsIndex = 0.05, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0, first_sample: typing.SupportsInt | typing.SupportsIndex = 0) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        SS (Eq. 3.4) of samples first_sample .. first_sample + samples - 1 (row r: sample first_sample + r) x top speeds with random structure; bit-rock uncertainty (Eq. 4.1) from eta rows (row r for row r of the result) sampled every eta_dt, or from a PSD on the generator grid of (eta_dt, duration) (Eq. 4.4).
        """
    @property
    def delta(self) -> numpy.typing.NDArray[numpy.float64]:
        ...
    @property
    def mean_matrices(self) -> dict:
        ...
    @property
    def model(self) -> str:
        ...
    @property
    def size(self) -> int:
        ...
class SeverityStatistics:
    """
    Statistics per top speed of SS samples (severity_statistics, section 4.2.2); arrays have one entry per speed.
    """
    def to_dict(self) -> dict:
        """
        Every field in a dict keyed by the field names.
        """
    @property
    def mean(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Sample mean of the stick-slip severity SS, Eq. (3.4), dimensionless.
        """
    @property
    def p_exceed(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Probability P(SS > level), dimensionless.
        """
    @property
    def p_speed(self) -> float:
        """
        Lowest top speed from which P(SS > level) <= prob [rad/s] (NaN: no crossing).
        """
    @property
    def q_high(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Upper quantile (q_high) of SS, dimensionless.
        """
    @property
    def q_low(self) -> numpy.typing.NDArray[numpy.float64]:
        """
        Lower quantile (q_low) of SS, dimensionless.
        """
class MonteCarlo:
    """
    Monte Carlo of the stochastic drill-string model (Algorithm 1).
    """
    def __init__(self, config: Config, psd: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], eta_dt: typing.SupportsFloat | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex, warmup: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        ...
    def eta(self, sample: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
        """
        The eta realization of one sample on its grid.
        """
    def phases(self, speed: typing.SupportsFloat | typing.SupportsIndex, first_sample: typing.SupportsInt | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[list, list, numpy.typing.NDArray[numpy.float64]]:
        """
        Stick and slip durations [s] per sample at one top speed, and SS.
        """
    def severity(self, speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], first_sample: typing.SupportsInt | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0, batched: bool = True) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        SS (Eq. 3.4) per sample (rows) and top speed (columns); batched: samples in SIMD lockstep where the batched integrator supports the configuration (False: the scalar reference integrator).
        """
    def severity_and_bit_speed(self, speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], first_sample: typing.SupportsInt | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex, threads: typing.SupportsInt | typing.SupportsIndex = 0) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]]:
        """
        SS (Eq. 3.4) and the mean bit speed of the SS window [rad/s] per sample (rows) and top speed (columns).
        """
    @property
    def eta_variance(self) -> float:
        ...
    @property
    def lockstep(self) -> bool:
        """
        Whether severity(batched=True) steps the samples in lockstep, one per lane (the torsional model where the batched integrator supports it; the axial-torsional model, axial.type = rgd, always): the same numbers as one by one.
        """
class HorizonStart:
    """
    Where one prediction horizon starts (drill/horizons.hpp): the model's state read off the record and the recorded channels that start the sensor filters.
    """
    @staticmethod
    def from_arrays(*, index: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], bit_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], bit_accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], torque: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], top_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], top_accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], y_bit_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], dy_bit_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], y_torque: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], dy_torque: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], y_top_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], dy_top_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], wob: typing.Any = None, dy_wob: typing.Any = None) -> list[HorizonStart]:
        """
        One HorizonStart per horizon from arrays with one entry per horizon (units of the fields; wob: the axial jack's WOB state [N], None: the set force; dy_wob: the recorded WOB's rate [N/s], None: 0).
        """
    def __init__(self, *, index: typing.SupportsInt | typing.SupportsIndex, bit_speed: typing.SupportsFloat | typing.SupportsIndex, bit_accel: typing.SupportsFloat | typing.SupportsIndex, torque: typing.SupportsFloat | typing.SupportsIndex, top_speed: typing.SupportsFloat | typing.SupportsIndex, top_accel: typing.SupportsFloat | typing.SupportsIndex, y_bit_speed: typing.SupportsFloat | typing.SupportsIndex, dy_bit_speed: typing.SupportsFloat | typing.SupportsIndex, y_torque: typing.SupportsFloat | typing.SupportsIndex, dy_torque: typing.SupportsFloat | typing.SupportsIndex, y_top_speed: typing.SupportsFloat | typing.SupportsIndex, dy_top_speed: typing.SupportsFloat | typing.SupportsIndex, wob: typing.SupportsFloat | typing.SupportsIndex = ..., dy_wob: typing.SupportsFloat | typing.SupportsIndex = 0.0) -> None:
        ...
    def __repr__(self) -> str:
        ...
    @property
    def bit_accel(self) -> float:
        """
        Bit acceleration of the model state [rad/s^2].
        """
    @property
    def bit_speed(self) -> float:
        """
        Bit speed of the model state [rad/s] (sensor effects removed).
        """
    @property
    def dy_bit_speed(self) -> float:
        """
        Rate of the recorded bit speed [rad/s^2].
        """
    @property
    def dy_top_speed(self) -> float:
        """
        Rate of the recorded top speed [rad/s^2].
        """
    @property
    def dy_torque(self) -> float:
        """
        Rate of the recorded torque [N m/s].
        """
    @property
    def dy_wob(self) -> float:
        """
        Rate of the recorded WOB at the restart [N/s]: with wob, the WOB sensor filter's state.
        """
    @property
    def index(self) -> int:
        """
        Sample of the input grid at which the horizon starts.
        """
    @property
    def top_accel(self) -> float:
        """
        Top acceleration of the model state [rad/s^2].
        """
    @property
    def top_speed(self) -> float:
        """
        Top speed of the model state [rad/s].
        """
    @property
    def torque(self) -> float:
        """
        Torque on bit of the model state [N m].
        """
    @property
    def wob(self) -> float:
        """
        WOB state of an axial jack at the restart [N] (drill/axial.hpp; NaN: the set force).
        """
    @property
    def y_bit_speed(self) -> float:
        """
        Recorded (filtered) bit speed [rad/s]: sensor filter state.
        """
    @property
    def y_top_speed(self) -> float:
        """
        Recorded (filtered) top speed [rad/s]: sensor filter state.
        """
    @property
    def y_torque(self) -> float:
        """
        Recorded (filtered) torque on bit [N m]: sensor filter state.
        """
class HorizonResult:
    """
    Predictions after the configured sensors (predict_horizons): row h, column j is the value (j + 1) dt after the start of horizon h.
    """
    def to_dict(self) -> dict:
        """
        Every field in a dict keyed by the field names.
        """
    @property
    def bit_speed(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Bit speed [rad/s], horizons x samples.
        """
    @property
    def top_speed(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Top speed [rad/s], horizons x samples.
        """
    @property
    def torque(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        Contact torque on bit [N m], horizons x samples.
        """
    @property
    def wob(self) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
        """
        WOB the law saw [N] (the axial jack's state, or the input), horizons x samples.
        """
def cb_frequencies(config: Config, n: typing.SupportsInt | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    First n natural frequencies [Hz] of the assembled Craig-Bampton model.
    """
def conv1(severity: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex]) -> list[float]:
    """
    Convergence function Conv1(n_s) of Eq. (C.1).
    """
def craig_bampton(config: Config) -> dict:
    """
    Craig-Bampton model of the configuration (Eqs. 6.8-6.18): assembled M, D, K, recovery Psi and the reduced blocks of each substructure.
    """
def exact_frequencies(config: Config, n: typing.SupportsInt | typing.SupportsIndex) -> list[float]:
    """
    First n exact natural frequencies [Hz] of the continuous string (transfer matrices).
    """
def fe_matrices(config: Config) -> dict:
    """
    Unconstrained global mass and stiffness matrices and node depths.
    """
def generate_process(psd: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.SupportsFloat | typing.SupportsIndex, duration: typing.SupportsFloat | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex, first_sample: typing.SupportsInt | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
    """
    Realizations of eta on the grid t = j dt (rows: samples first_sample ..), the same as the Monte Carlo samples with that seed.
    """
def law_torque(law: str, speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], acceleration: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], wob: typing.Annotated[numpy.typing.ArrayLike, numpy.float64]) -> tuple[numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64], numpy.typing.NDArray[numpy.float64]]:
    """
    Torque on bit [N m] and its derivatives w.r.t. bit speed [rad/s] and acceleration [rad/s^2] (Eqs. 3.1-3.3, 5.1, 5.3).
    """
def lowpass2(x: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], cutoff_hz: typing.SupportsFloat | typing.SupportsIndex, dt: typing.SupportsFloat | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    The measurement chain of drill/sensor.hpp (second-order Butterworth, trapezoidal rule) over a series sampled every dt [s], started at rest on its first value.
    """
def max_dispersion(n: typing.SupportsInt | typing.SupportsIndex) -> float:
    """
    Upper bound sqrt((n+1)/(n+5)) of the dispersion of SG+ in dimension n (excluded).
    """
def max_threads() -> int:
    """
    Number of OpenMP threads the engine uses by default.
    """
def natural_frequencies(config: Config, n: typing.SupportsInt | typing.SupportsIndex) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    First n natural frequencies [Hz] of the clamped string (Eq. 2.7).
    """
def normalize_config(config: Config) -> str:
    """
    Validated configuration as JSON text with every default made explicit.
    """
def observation_nodes(config: Config) -> list[int]:
    """
    P_obs,1 (first free node), P_obs,2 (first interface), P_obs,3 (bit) of section 6.6.
    """
def predict_horizons(simulation: Simulation, starts: collections.abc.Sequence[HorizonStart], dt: typing.SupportsFloat | typing.SupportsIndex, samples: typing.SupportsInt | typing.SupportsIndex, top_speed: typing.Any = None, wob: typing.Any = None, eta: typing.Any = None, progress: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0, batched: bool = True) -> HorizonResult:
    """
    Short-horizon predictions restarted from measured states (drill/horizons.hpp), one per HorizonStart, samples dt [s] apart; top_speed [rad/s] and wob [N] are input series on the record's grid (default: the operating point), eta horizons x (samples + 1) the bit-rock fluctuation of Eq. (4.1); batched: horizons in SIMD lockstep with an ideal top drive (False: the scalar reference integrator).
    """
def predict_horizons_many(simulations: collections.abc.Sequence, starts: collections.abc.Sequence[collections.abc.Sequence[HorizonStart]], dt: typing.SupportsFloat | typing.SupportsIndex, samples: collections.abc.Sequence[typing.SupportsInt | typing.SupportsIndex], top_speed: typing.Any = None, wob: typing.Any = None, eta: typing.Any = None, threads: typing.SupportsInt | typing.SupportsIndex = 0, batched: bool = True) -> list:
    """
    predict_horizons for several simulations in one parallel region (the loop's Jacobian: one simulation per perturbed model): entry i of starts, samples and of the optional top_speed, wob, eta lists (None or an array per simulation) are call i's arguments. Returns one entry per simulation: the HorizonResult predict_horizons gives, bit for bit, or the exception it raises (ValueError, RuntimeError, ...) as an object, not raised: one model's failure leaves the others' predictions.
    """
def preset_json(arg0: str) -> str:
    """
    JSON text of a built-in preset.
    """
def preset_names() -> list[str]:
    """
    Names of the built-in presets.
    """
def process_grid(dt: typing.SupportsFloat | typing.SupportsIndex, duration: typing.SupportsFloat | typing.SupportsIndex) -> list[float]:
    """
    Frequencies [Hz] at which the generator needs the PSD (k / (n dt), k = 0 .. n/2).
    """
def process_variance(psd: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], dt: typing.SupportsFloat | typing.SupportsIndex, duration: typing.SupportsFloat | typing.SupportsIndex) -> float:
    """
    Exact variance of the generated process (trapezoidal sum of the PSD on the grid).
    """
def psd_model_integral(f0: typing.SupportsFloat | typing.SupportsIndex, A0: typing.SupportsFloat | typing.SupportsIndex, a: typing.SupportsFloat | typing.SupportsIndex, b: typing.SupportsFloat | typing.SupportsIndex, fmax: typing.SupportsFloat | typing.SupportsIndex = ...) -> float:
    """
    integral_0^fmax S(f) df of the model of Eq. (4.4) (the variance of eta for fmax = inf).
    """
def psd_model_values(f: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f0: typing.SupportsFloat | typing.SupportsIndex, A0: typing.SupportsFloat | typing.SupportsIndex, a: typing.SupportsFloat | typing.SupportsIndex, b: typing.SupportsFloat | typing.SupportsIndex) -> numpy.typing.NDArray[numpy.float64]:
    """
    PSD model of Eq. (4.4) (natural log; one-sided, per Hz) at frequencies f [Hz].
    """
def psd_table_values(table_f: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], table_S: typing.Annotated[numpy.typing.ArrayLike, numpy.float64], f: typing.Annotated[numpy.typing.ArrayLike, numpy.float64]) -> numpy.typing.NDArray[numpy.float64]:
    """
    Tabulated PSD (linear between points, held below the first, zero above the last) at f [Hz].
    """
def random_matrix(mean: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], delta: typing.SupportsFloat | typing.SupportsIndex, seed: typing.SupportsInt | typing.SupportsIndex = 1, sample: typing.SupportsInt | typing.SupportsIndex = 0) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, n]"]:
    """
    One realization of SE+ (positive-definite mean, Eqs. 6.1-6.2) or SE+0 (semi-definite mean, Eqs. 6.24-6.25) with dispersion delta (Eq. 6.3).
    """
def run_many(simulations: collections.abc.Sequence[Simulation], top_speed_series: typing.Any = None, series_dt: typing.SupportsFloat | typing.SupportsIndex = 0.001, series_t0: typing.SupportsFloat | typing.SupportsIndex = 0.0, record: bool = True, threads: typing.SupportsInt | typing.SupportsIndex = 0, batched: bool = True) -> tuple[list, list[str]]:
    """
    Independent runs of several simulations at their configured operation points (drill/run_many.hpp), in parallel and, where the models differ at most in their modal damping and the batched integrator supports them, in SIMD lockstep (their series then lack bit_angle and top_torque); top_speed_series, sampled every series_dt from series_t0, drives every run. Returns (reports, errors): a run that failed has report None and its error message, the others an empty message.
    """
def severity_statistics(severity: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, n]"], speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], level: typing.SupportsFloat | typing.SupportsIndex = 0.5, prob: typing.SupportsFloat | typing.SupportsIndex = 0.05, q_low: typing.SupportsFloat | typing.SupportsIndex = 0.05, q_high: typing.SupportsFloat | typing.SupportsIndex = 0.95) -> SeverityStatistics:
    """
    Mean, quantiles and P(SS > level) per speed; the speed from which P(SS > level) <= prob.
    """
def severity_threshold(speeds: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], severities: collections.abc.Sequence[typing.SupportsFloat | typing.SupportsIndex], level: typing.SupportsFloat | typing.SupportsIndex = 0.5) -> float:
    """
    Top speed below which SS > level (NaN if the curve does not cross the level).
    """
def state_from_bit(simulation: Simulation, bit_speed: typing.SupportsFloat | typing.SupportsIndex, bit_accel: typing.SupportsFloat | typing.SupportsIndex, torque: typing.SupportsFloat | typing.SupportsIndex, top_speed: typing.SupportsFloat | typing.SupportsIndex, top_accel: typing.SupportsFloat | typing.SupportsIndex) -> tuple[typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"], typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]]:
    """
    Reduced state (q, q') reproducing a measured bit state (Eq. 2.9).
    """
def thesis_case_dispersions(case: typing.SupportsInt | typing.SupportsIndex, delta: typing.SupportsFloat | typing.SupportsIndex = 0.1) -> numpy.typing.NDArray[numpy.float64]:
    """
    Dispersions (2, 3, 2) of case studies 1-7 (Tables 6.1-6.7): [DP, BHA] x [M, D, K] x [inner, interface].
    """
def top_torque_from_bit(simulation: Simulation, bit_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], bit_accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], torque: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], top_speed: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"], top_accel: typing.Annotated[numpy.typing.ArrayLike, numpy.float64, "[m, 1]"]) -> typing.Annotated[numpy.typing.NDArray[numpy.float64], "[m, 1]"]:
    """
    Elastic torque at the top [N m] of the states reproducing measured bit states (one per sample).
    """
def with_total_elements(config: Config, elements: typing.SupportsInt | typing.SupportsIndex) -> Config:
    """
    Re-mesh with n elements split in proportion to the section lengths (largest remainder).
    """

"""The protocol every effect of the loop's catalogue follows (one module per effect).

An effect is a named change of the declared model with its own parameters. Its module defines one
:class:`Effect` subclass instance that says

* what it is: ``level`` (``"law"``: fitted with the bit-rock law on the law residual first;
  ``"dynamic"``: fitted on the short-horizon predictions), its parameters (:class:`Param`: unit,
  physical bounds, the value at which the effect is absent), the model change, the signature it
  leaves in the residual of a model without it and its physical reading on the test rig;
* how it is fitted: :meth:`Effect.starts` (starting parameter sets);
* how it changes the engine configuration: :meth:`Effect.configure`; how a declared configuration
  carries it: :meth:`Effect.declared` and :meth:`Effect.strip`;
* how it changes a prediction restarted from the record (only the effects that act through the
  record's inputs or the sensors override these): :meth:`Effect.delay_s`, :meth:`Effect.undo`, :meth:`Effect.torque_sensor`,
  :meth:`Effect.top_state`, :meth:`Effect.wob_input`, :meth:`Effect.eta`, :meth:`Effect.restart_torque`,
  :meth:`Effect.restart_wob`;
* what is physically implausible about a fit: :meth:`Effect.flags`;
* how the synthetic generator puts it into a record: :meth:`Effect.inject`.

Conventions shared by the hooks: ``p`` is the effect's parameter dict (parameter name -> value in
the unit of its :class:`Param`, SI; some effects also keep non-numeric entries such as
``"variant"`` or ``"source"``); ``model`` is a :class:`drillpy.loop.model.LoopModel`; ``data`` is the
record on the analysis grid, a :class:`drillpy.loop.data.LoopData`; ``chs`` are the state channels
of :func:`drillpy.loop.model.state_channels` (``v`` bit speed [rad/s], ``a`` bit acceleration
[rad/s^2], ``T`` torque on bit [N m], ``top``/``dtop`` top speed [rad/s] and its rate [rad/s^2],
``W`` recorded WOB [N], ``W_eff`` the law's WOB input [N]); ``idx`` are the restart sample indices
on that grid (one per horizon); ``cfg`` is an engine configuration dict
(:func:`drillpy.model.config.normalize`).

Configurations: :meth:`Effect.declared` reads ``cfg`` by attribute (a dict or a
:class:`~drillpy.model.configuration.Configuration`, through :func:`drillpy.loop.view.view`, no copy);
:meth:`Effect.configure` and :meth:`Effect.strip` edit a dict in place, the loop's JSON edge: configure
runs on every trial's configuration (:meth:`drillpy.loop.model.LoopModel.engine_config`, straight into
``_core.Config.from_dict``), where a copy or a schema lookup per effect would cost on every trial, and
strip also edits partial holders (a law and an operation block).
"""
from __future__ import annotations

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class Param:
    """A parameter of an effect: physical bounds of the fit, the value at which the effect is
    absent (``null``; None when no finite value removes it), the margin around it within which a
    value is no effect (``margin``: the declared model's own tolerance, e.g. a bar's GJ from its
    nominal dimensions), and whether it is fitted on the short horizons (``scale``: ``"lin"`` or
    ``"log"``, the latter fitted in ln) or estimated otherwise (``fitted`` False: reported only).

    Attributes
    ----------
    name : str
        Key of the parameter in the effect's parameter dict and in ``loop.json``/``model.json``
        (e.g. ``"lowpass_hz"``, ``"static_torque_nm"``).
    unit : str
        Unit of the value, as reported (e.g. ``"Hz"``, ``"N m"``, ``"-"`` for a ratio).
    meaning : str
        Physical meaning, with the symbol of docs/loop.md (e.g. ``"T_s: torque the string must
        exceed to break the stuck bit away"``); :func:`drillpy.reports.loop.reading` prints it.
    lower, upper : float
        Physical bounds of the fit, in ``unit`` (default unbounded). An effect may narrow them for a
        given model (:meth:`Effect.bounds`); a fitted value within 1e-3 of the (fitted) span from a bound
        is "at its bound" (:func:`drillpy.loop.fitting.parameter_evidence`).
    scale : str
        ``"lin"``: fitted as is; ``"log"``: fitted in ln (the bounds must then be positive).
    null : float or None
        Value at which the effect is absent (e.g. 0 N m of static torque, a GJ factor of 1); the
        effect is credited only when the parameter's 95 % interval excludes it. None: no finite
        value removes the effect (e.g. a filter cutoff).
    fitted : bool
        True: calibrated on the short horizons; False: estimated otherwise and reported only (e.g.
        the standard deviation of ``torque_fluctuation``).
    margin : float
        Half-width, in ``unit``, of the band around ``null`` that still counts as no effect (the
        declared model's own tolerance; 0.03 for the GJ factor: a bar radius known to +-0.75 %).
    binding : bool
        True: a fit at a bound means the effect is not identified (it is not credited); False: a
        shape parameter (e.g. ``beta2``) whose value at a bound is only flagged.
    """
    name: str
    unit: str
    meaning: str
    lower: float = -math.inf
    upper: float = math.inf
    scale: str = "lin"
    null: float | None = None
    fitted: bool = True
    margin: float = 0.0
    binding: bool = True  #: a fit at a bound means the effect is not identified (False: a shape parameter, flagged only)


class Effect:
    """Base class of the catalogue's effects; see the module docstring for the protocol.

    Subclasses set the class attributes below and override the hooks their effect needs; the
    defaults are those of an effect that acts through the engine configuration alone.

    Attributes
    ----------
    name : str
        Catalogue name (a key of :data:`drillpy.loop.effects.CATALOGUE`, the ``effects`` of
        ``loop.json``).
    level : str
        ``"law"``: a change of the bit-rock law, fitted on the law residual T - T_law(v, a, W) first
        and required to lower it (:func:`drillpy.loop.evidence.law_evidence`); ``"dynamic"``:
        fitted on the short-horizon predictions only.
    params : tuple of Param
        The effect's parameters (bounds, no-effect value, margin).
    change : str
        The model change, as an equation in words (reported).
    signature : str
        What the effect leaves in the residual of a model without it (reported).
    reading : str
        Its physical reading on the test rig (reported, :func:`drillpy.reports.loop.reading`).
    needs : tuple of str
        Record channels the effect needs besides bit speed and torque (``"top_speed"``, ``"wob"``);
        it is not a candidate on a record without them.
    confounded_with : tuple of str
        What it cannot be told from in some conditions (``"damping"``: not a candidate while the
        damping ratios are held by the limit cycle).
    wob_state : bool
        True: the effect makes the WOB a state of the model (the law's WOB in the law fit is then
        the recorded WOB, and the restarts start the state from it, :meth:`restart_wob`).
    reshapes_law : bool
        True: the effect rewrites part of the law (e.g. its static branch), so a candidate is also
        started from the law refitted on the law residual with it.
    defaults : dict
        Parameters of the synthetic truth when the effect is switched on without values
        (:mod:`drillpy.loop.synthetic`; the keys are those :meth:`inject` reads).
    law_keys : tuple of str
        Keys of the law's own optional term that the effect stands for (``bit_hysteresis``: beta1
        and beta2 of Eq. 3.3): with the effect in the model the law is fitted in its family with
        that term, and the effect's values are read back from the fitted law (:meth:`from_law`).
    inject_last : bool
        True: :meth:`inject` reads what the other effects put into the truth's configuration (a
        motor's command depends on the law and the extra torques), so it runs after them.
    confounded_note : str
        What the final model's note says when the damping ratios come out implausibly high and the
        effect, confounded with the damping (:attr:`confounded_with`), is not in the model.
    """
    name: str = ""
    level: str = "dynamic"
    params: tuple = ()
    change: str = ""
    signature: str = ""
    reading: str = ""
    needs: tuple = ()
    confounded_with: tuple = ()  #: effects it cannot be told from in some conditions (documented per effect)
    #: the effect rewrites part of the law (e.g. its static branch): a candidate is started from the
    #: law refitted on the law residual with it as well as from the current law (which, without the
    #: effect, may have bent to mimic it)
    reshapes_law: bool = False
    #: the effect makes the WOB a state of the model (an axial model): the law then sees the state,
    #: whose measurement is the recorded WOB, in the law fit and at the restarts
    wob_state: bool = False
    #: keys of the law's optional term the effect stands for (read back from the fitted law)
    law_keys: tuple = ()
    #: the effect's injection reads the other effects' changes of the truth: it runs after them
    inject_last: bool = False
    #: the final note's words on the effect when it is confounded with implausibly high damping
    confounded_note: str = ""

    # ------------------------------------------------------------------ parameters and fits
    def free(self, p: dict) -> tuple:
        """The parameters fitted on the short horizons for these values (default: every fitted one
        of a ``"dynamic"`` effect; none of a ``"law"`` effect, whose parameters the law fit carries).

        Parameters
        ----------
        p : dict
            The effect's current parameter values (name -> value in the :class:`Param`'s unit; may
            hold a ``"variant"`` or ``"source"`` entry that decides which parameters are free).

        Returns
        -------
        tuple of Param
            The parameters :func:`drillpy.loop.fitting.fit_dynamic` varies, each within
            :meth:`bounds` and on its ``scale``.
        """
        return tuple(q for q in self.params if q.fitted) if self.level == "dynamic" else ()

    def count(self, p: dict) -> int:
        """Number of calibrated parameters the effect adds (for the information criterion).

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).

        Returns
        -------
        int
            dk of the BIC, dBIC = n_eff ln(E_null^2 / E^2) - dk ln(n_eff)
            (:func:`drillpy.loop.evidence.evidence`); default the number of :meth:`free`
            parameters (a law-level effect overrides it: its parameters are fitted with the law).
        """
        return len(self.free(p))

    def law_params(self, p: dict) -> tuple:
        """Parameters fitted jointly with the law's own, on the law residual
        (:func:`drillpy.loop.fitting.fit_law`) and in the law's block of the short-horizon fits
        (default: none; ``wob_coupling``: its gain k, which sets the law's WOB input through
        :meth:`wob_input`).

        Parameters
        ----------
        p : dict
            The effect's current parameter values (name -> value).

        Returns
        -------
        tuple of Param
            The parameters, each within :meth:`bounds` (a missing value starts at :attr:`defaults`).
        """
        return ()

    def from_law(self, law: dict) -> dict:
        """The effect's values read back from a fitted law (the keys of :attr:`law_keys`).

        Parameters
        ----------
        law : dict
            The law block of the engine configuration, as fitted.

        Returns
        -------
        dict
            Parameter name -> value (empty when the effect owns no law keys).
        """
        return {k: float(law[k]) for k in self.law_keys}

    def estimate(self, p: dict, slip) -> dict:
        """Values estimated outside the fits after every calibration (the parameters with
        ``fitted`` False that are not set by the fit itself; default: none).

        Parameters
        ----------
        p : dict
            The effect's values after the calibration.
        slip : callable
            ``slip()`` returns (T, T_law) [N m]: the torque with the model's measurement chain
            undone and the calibrated law's torque on the calibration part's slip samples
            (computed once per calibration, on the first call).

        Returns
        -------
        dict
            Parameter name -> value, merged into ``p``.
        """
        return {}

    def feeds_cycle(self, p: dict) -> bool:
        """Whether the effect feeds the model a recorded channel that carries the stick-slip cycle
        (the measured top speed as a kinematic drive): such a model explains a record, it does not
        predict it (default False).

        Parameters
        ----------
        p : dict
            The effect's values (e.g. its ``"variant"``).

        Returns
        -------
        bool
            True makes :attr:`drillpy.loop.model.LoopModel.predictive` False.
        """
        return False

    def bounds(self, q: Param, model) -> tuple:
        """(lower, upper) of a parameter's fit for this model (default: the parameter's own).

        Parameters
        ----------
        q : Param
            One of the effect's parameters.
        model : LoopModel
            The model being calibrated (e.g. its engine step bounds a motor inertia from below).

        Returns
        -------
        tuple of float
            (lower, upper) in the parameter's unit (not in ln, whatever its ``scale``).
        """
        return q.lower, q.upper

    def starts(self, model, data) -> list:
        """Starting parameter sets of the fit (the best on the calibration horizons is refined).

        :func:`drillpy.loop.fitting.fit_candidate` evaluates E on the calibration horizons for every
        start (and, when :attr:`reshapes_law`, for every start with the law refitted) and
        calibrates the best one. Not used for ``"law"`` effects (they start from :attr:`defaults`
        and the law fit).

        Parameters
        ----------
        model : LoopModel
            The current model, without the effect.
        data : LoopData
            The record on the analysis grid; only its calibration part may be used.

        Returns
        -------
        list of dict
            Parameter dicts (name -> value in the :class:`Param`'s unit).
        """
        raise NotImplementedError(self.name)

    def applicable(self, data) -> bool:
        """Whether the record shows the effect's precondition, so that it is a candidate (default:
        True; the channels of :attr:`needs` are checked apart).

        Parameters
        ----------
        data : LoopData
            The record on the analysis grid.

        Returns
        -------
        bool
            False keeps the effect out of the candidates on this record.
        """
        return True

    def direct(self, model, data) -> dict | None:
        """A direct measurement of the effect from the record's calibration part, independent of
        the short-horizon fit, or None when the effect has none (default).

        When the measurement is significant the candidate is started from the measured value (an
        effect may hold it there through :meth:`free`) and the measurement is recorded in its
        evidence; it proposes the candidate but never replaces the validation test (docs/loop.md,
        "direct evidence"; issue 29).

        Parameters
        ----------
        model : LoopModel
            The current model, without the effect.
        data : LoopData
            The record on the analysis grid.

        Returns
        -------
        dict or None
            ``{"params": {...}, "ci95": {name: [lo, hi]}, "significant": bool, "detail": str}``:
            ``params`` the measured parameter dict (with a ``"source"`` entry), ``ci95`` the 95 %
            interval of each parameter in its unit, ``detail`` one line for the report.
        """
        return None

    def describe(self, p: dict) -> str:
        """One sentence on the fitted values, for the report's physical reading
        (:func:`drillpy.reports.loop.reading` appends :attr:`reading`); default: every parameter's
        meaning, value and unit.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value in the parameter's unit).

        Returns
        -------
        str
            The sentence, without a final full stop.
        """
        return "; ".join(f"{q.meaning}: {p[q.name]:.4g} {q.unit}" for q in self.params if q.name in p)

    def flags(self, p: dict, data, model=None) -> list:
        """Reasons why fitted values are physically implausible (an empty list: plausible).

        A non-empty list keeps the effect from being credited
        (:func:`drillpy.loop.fitting.parameter_evidence`).

        Parameters
        ----------
        p : dict
            The fitted parameter values (name -> value).
        data : LoopData
            The record on the analysis grid (e.g. its sampling interval ``dt`` [s]).
        model : LoopModel, optional
            The fitted model with the effect (e.g. its calibrated law).

        Returns
        -------
        list of str
            One sentence per reason, for ``evidence.json`` and the report.
        """
        return []

    # --------------------------------------------------------------- engine configuration
    def declared(self, cfg: dict) -> dict | None:
        """The effect's parameters if a declared configuration already has it, else None.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration (normalized).

        Returns
        -------
        dict or None
            Parameter dict (name -> value in the :class:`Param`'s unit) read from ``cfg``; these
            become the model's declared effects and their starts
            (:func:`drillpy.loop.effects.declared_effects`).
        """
        return None

    def strip(self, cfg: dict) -> None:
        """Remove the effect from a configuration (in place): the value that makes it absent.

        Parameters
        ----------
        cfg : dict
            An engine configuration (or a part of one with at least the keys the effect touches:
            ``law``, ``operation``, ``string``); modified in place.
        """

    def configure(self, cfg: dict, p: dict, model) -> None:
        """Put the effect with parameters ``p`` into the engine configuration ``cfg`` (in place).

        Called by :meth:`drillpy.loop.model.LoopModel.engine_config` on a configuration that already
        carries the model's law and operating point, and by :meth:`inject` on a synthetic truth's.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            The effect's parameter values (name -> value in the :class:`Param`'s unit).
        model : LoopModel or None
            The model being configured; None when a synthetic truth is configured.
        """

    # ------------------------------------------------------- predictions from the record
    def delay_s(self, p: dict) -> float:
        """Delay of the recorded channels behind the model's state [s] (sensors).

        :func:`drillpy.loop.model.state_channels` reads the model's state at t off the record at
        t + delay, and :func:`drillpy.loop.model.predict` restarts each horizon that much earlier.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).

        Returns
        -------
        float
            Delay [s]; 0 (default) for an effect without a measurement chain.
        """
        return 0.0

    def undo(self, p: dict) -> tuple:
        """(c1, c2) of a second-order measurement chain undone as x = y + c1 y' + c2 y''.

        :func:`drillpy.loop.model.law_channels` undoes the chain on the recorded channels y before
        the law residual is formed (the coefficients of several effects add).

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).

        Returns
        -------
        tuple of float
            c1 [s] and c2 [s^2]; (0, 0) (default) for an effect without a measurement chain.
        """
        return 0.0, 0.0

    def top_state(self, p: dict, model, chs: dict, idx):
        """(top speed, its rate, top-speed series driving the top or None) at the restarts, or None
        when the effect does not change the top boundary.

        Without an effect that overrides it, the top turns at the model's constant ``top_speed``
        [rad/s] (the ideal drive). Also called by :func:`drillpy.loop.longrun.simulate_record` with
        ``chs = {"top": ..., "dtop": zeros}`` on the record's own grid and ``idx = [0]``, where only
        the series is used.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value; may hold ``"variant"``).
        model : LoopModel
            The model being predicted.
        chs : dict
            State channels (``top`` [rad/s] and ``dtop`` [rad/s^2] are read).
        idx : array_like of int
            Restart sample indices.

        Returns
        -------
        tuple or None
            (top speed [rad/s] at each restart, its rate [rad/s^2] at each restart (NaN: the
            engine takes it from the drive's own equation), the series [rad/s] on the grid of
            ``chs`` that drives the top kinematically or None for a drive with its own dynamics),
            or None (default).
        """
        return None

    def wob_input(self, p: dict, model, w):
        """The law's WOB input from the recorded WOB ``w`` (None: the effect does not change it).

        Without an effect that overrides it, the law is evaluated at the model's constant WOB W_0
        (``model.wob`` [N]).

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).
        model : LoopModel
            The model (its ``wob`` W_0 [N]).
        w : numpy.ndarray or None
            Recorded WOB [N] per sample, or None when the record has no WOB channel.

        Returns
        -------
        numpy.ndarray or None
            The WOB W_eff [N] the law takes, per sample of ``w``; None (default) when the effect
            does not change it (or ``w`` is None).
        """
        return None

    def eta(self, p: dict, model, data, chs: dict, idx, leads):
        """Forecast of the relative torque fluctuation at the restarts (rows) and leads [s] (columns).

        The engine multiplies the law's torque by (1 + eta) over each horizon, T = T_law (1 + eta)
        (Eq. 4.1).

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).
        model : LoopModel
            The model being predicted (its law T_law).
        data : LoopData
            The record on the analysis grid.
        chs : dict
            State channels (:func:`drillpy.loop.model.state_channels`).
        idx : array_like of int
            Restart sample indices (one per horizon).
        leads : numpy.ndarray
            Times after the restart [s], one per engine output sample of a horizon (0, dt, 2 dt, ...).

        Returns
        -------
        numpy.ndarray or None
            eta [-], shape (len(idx), len(leads)); None (default) for an effect without a torque
            fluctuation.
        """
        return None

    def restart_torque(self, p: dict, model, data, chs: dict, idx):
        """Correction [N m] of the total torque on the bit at the restarts ``idx`` (added to the
        measured torque on bit of the restart state, after the engine's own T_sf sign(v) and c_v v),
        or None: for effects whose share of the torque on a bit near rest the measured speed does not
        determine.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).
        model : LoopModel
            The model being predicted.
        data : LoopData
            The record on the analysis grid (its stick threshold [rad/s]).
        chs : dict
            State channels (:func:`drillpy.loop.model.state_channels`).
        idx : array_like of int
            Restart sample indices (one per horizon).

        Returns
        -------
        numpy.ndarray or None
            Torque [N m] added to the restart state's torque on bit, one value per restart; None
            (default) when the effect needs no correction.
        """
        return None

    def restart_wob(self, p: dict, model, data, chs: dict, idx):
        """The WOB state [N] at the restarts ``idx`` of an effect that makes the WOB a state of the
        model (an axial model), or None (default: the WOB is an input).

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).
        model : LoopModel
            The model being predicted.
        data : LoopData
            The record on the analysis grid.
        chs : dict
            State channels (:func:`drillpy.loop.model.state_channels`).
        idx : array_like of int
            Restart sample indices (one per horizon).

        Returns
        -------
        numpy.ndarray or None
            WOB [N], one value per restart; None (default).
        """
        return None

    def torque_sensor(self, p: dict) -> tuple:
        """(s, b) of the torque channel's calibration, recorded torque = s T + b (docs/loop.md, `sensor_gain`).

        :func:`drillpy.loop.model.torque_sensor` composes them; the model's state, its law residual
        and its restart torque take the true torque (T_rec - b) / s, and its predicted torque is
        compared with the record as s T_pred + b.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).

        Returns
        -------
        tuple of float
            Scale s [-] and offset b [N m]; (1, 0) (default) for an effect that does not touch the
            torque channel's calibration.
        """
        return 1.0, 0.0

    def measure(self, p: dict, chans: dict, fs: float) -> dict:
        """The recorded channels of a simulation (dict name -> array at ``fs`` Hz) after the effect's
        measurement chain (default: unchanged).

        Used by the long-run check (:func:`drillpy.loop.longrun.simulate_record`) so that the
        simulated record is seen through the same sensors as the measured one.

        Parameters
        ----------
        p : dict
            The effect's parameter values (name -> value).
        chans : dict
            Simulated channels (``bit_speed`` [rad/s], ``top_speed`` [rad/s], ``torque_on_bit``
            [N m]), name -> 1-D array.
        fs : float
            Their sampling rate [Hz].

        Returns
        -------
        dict
            The channels as recorded (same keys and lengths).
        """
        return chans

    # ------------------------------------------------------------------------ synthetic truth
    def inject(self, truth, p: dict) -> None:
        """Switch the effect on in a synthetic truth (:class:`drillpy.loop.synthetic.Truth`).

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth being built; its configuration ``cfg`` (edited in place or replaced
            by a changed copy: read ``truth.cfg`` after), input series (``wob``, ``wob_law``, ``eta``,
            ``top``) or measurement functions ``post`` are changed.
        p : dict
            The truth's parameters of the effect: :attr:`defaults` updated with the caller's values
            (the keys of :attr:`defaults`, which may differ from the fitted :attr:`params`).
        """
        raise NotImplementedError(self.name)

    defaults: dict = {}  #: parameters of the synthetic truth when switched on without values

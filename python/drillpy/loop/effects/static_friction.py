"""``static_friction``: a break-away torque at the bit (the non-regularized Eq. 5.1, a0 > 0)."""
from __future__ import annotations

import numpy as np

from .base import Effect, Param
from ..view import view


def _a0(law: dict, torque: float, wob: float) -> float:
    """a0 of Eq. (5.1) whose static torque gain a0 W / W_ref is ``torque`` at ``wob``."""
    return float(torque) * float(law["wob_ref_n"]) / (float(law["gain"]) * float(wob))


#: A break-away torque must exceed the sliding law's largest torque by this factor.
ABOVE_SLIDING = 1.05


def sliding_peak(model, data) -> float:
    """The largest torque [N m] the model's law (without static torque) gives at its WOB W_0 over
    the calibration part's speeds, from 5 % of the stick threshold to the 99th percentile.

    Parameters
    ----------
    model : LoopModel
        The model (a polynomial ``law``, ``wob`` [N]).
    data : LoopData
        The record on the analysis grid.
    """
    from drillpy.records import identification as ident
    cal = data.valid & (data.t < data.t_split)
    v = np.linspace(0.05 * data.stick_threshold, float(np.percentile(data.ch["v"][cal], 99)), 200)
    return float(np.max(ident.law_eval(model.law, v, np.zeros(v.size), np.full(v.size, model.wob))[0]))


class StaticFriction(Effect):
    """A break-away (static) torque T_s at the bit: the non-regularized law of Eq. (5.1) with
    a0 > 0 (polynomial laws only), a1 re-tied so that the law falls linearly from T_s to the slip
    branch.

    Parameter ``static_torque_nm`` T_s [N m] (0-20, absent at 0), the static torque gain
    a0 W / W_ref of Eq. (5.1). Measured directly from the calibration part's stick phases
    (:meth:`direct`); when that measurement is significant it is held, not fitted.
    """
    name = "static_friction"
    params = (Param("static_torque_nm", "N m", "T_s: torque the string must exceed to break the stuck bit away "
                    "(gain a0 W / W_ref of Eq. 5.1)", 0.0, 20.0, null=0.0),)
    change = ("the law's static torque: the bit stays stuck while the string torque is below T_s (Eq. 5.1 with "
              "a0 > 0; a1 re-tied so that the law falls linearly from T_s to the slip branch)")
    signature = ("bit-speed residuals at the stick-slip transitions: the measured bit stays stuck after the model's "
                 "breaks away, and the torque keeps rising while the model's drops")
    reading = ("the rock holder's break-away (static) friction: the bit sticks, the string winds up, and it breaks "
               "away at a torque above the sliding one (the stick phases of the rig, e.g. at 28-30 s of sample 175)")
    #: a calibrated reversible law raises its low-speed peak to mimic a break-away (docs/loop.md)
    reshapes_law = True
    #: Synthetic truth: 4.5 N m, 1.7 x the declared law's torque at low speed (2.69 N m at 0.1 rad/s).
    defaults = {"static_torque_nm": 4.5}

    def _check(self, law):
        if not str(law["type"]).startswith("polynomial"):
            raise ValueError(f"static_friction: the law {law['type']!r} has no static torque (Eq. 5.1 needed)")

    def free(self, p):
        """None when T_s was measured from the stick phases (``p["source"] == "stick phases"``: it
        is held at the measured value), else T_s; see :meth:`Effect.free`.

        Parameters
        ----------
        p : dict
            ``{"static_torque_nm": T_s [N m]}``, possibly with ``"source"``.
        """
        return () if p.get("source") == "stick phases" else self.params

    def direct(self, model, data):
        """The break-away torque of every stick phase of the calibration part (the largest torque
        from the start of the stick to just after it ends, scaled to the model's WOB:
        :func:`drillpy.records.identification.breakaway_torques`), its mean with a Student-t interval over
        the stick phases; significant when the interval lies above the law's largest torque over the
        record's speeds by more than 5 % (below that it is the law's own peak).

        Each break-away torque is scaled by W_0 / W_eff with the WOB the *model's* law takes at that
        instant (``W_eff`` of :func:`..model.state_channels`): the static torque gain a0 W / W_ref
        follows the recorded WOB only in a model whose law takes it (``wob_coupling``); in a model
        at the constant W_0 the break-away torques are compared as measured. (Scaling them by a
        recorded WOB the model's static torque does not follow turns its fluctuation into scatter
        and, by Jensen's inequality, into a bias E[W_0 / W] - 1 ~ sd(W / W_0)^2, +2 % at the rig's
        14 %: on the validation's full-size case 4.651 N m [4.459, 4.843] against 4.481 [4.477, 4.485]
        as measured, the truth's being 4.5; the short-horizon fit cannot correct it, T_s being held
        at the measured value.)

        See :meth:`Effect.direct`.

        Parameters
        ----------
        model : LoopModel
            The current model (its law, WOB W_0 [N] and law WOB input W_eff).
        data : LoopData
            The record on the analysis grid; only its calibration part is used.

        Returns
        -------
        dict or None
            ``params`` ``{"static_torque_nm": mean break-away torque [N m], "source": "stick
            phases"}``, its 95 % interval, ``significant`` and ``detail``; None for a law that is
            not polynomial or with fewer than 3 stick phases.
        """
        if not str(model.law["type"]).startswith("polynomial"):
            return None
        from scipy import stats
        from drillpy.records import identification as ident
        from drillpy.records.signals import segment_cycles
        cal = data.valid & (data.t < data.t_split)
        cyc = segment_cycles(data.ch["v"], data.dt, data.stick_threshold, valid=cal)
        from ..model import state_channels, true_torque
        w = state_channels(model, data)["W_eff"]
        T = true_torque(model, data.ch["T"])  # the load cell's calibration undone (sensor_gain)
        brk = ident.breakaway_torques(cyc, np.where(cal, T, np.nan), w, model.wob)
        if brk.size < 3:
            return None
        m, se = float(np.mean(brk)), float(np.std(brk, ddof=1) / np.sqrt(brk.size))
        h = float(stats.t.ppf(0.975, brk.size - 1)) * se
        # a break-away torque (the peak just after the bit leaves) below the law's own peak is that
        # peak, not a static friction
        t_low = sliding_peak(model, data)
        return {"params": {"static_torque_nm": m, "source": "stick phases"},
                "ci95": {"static_torque_nm": [m - h, m + h]}, "significant": bool(m - h > ABOVE_SLIDING * t_low),
                "detail": f"break-away torque {m:.3f} N m [{m - h:.3f}, {m + h:.3f}] over {brk.size} stick phases "
                          f"against the law's largest torque {t_low:.3f} N m"}

    def flags(self, p, data, model=None):
        """Flag a static torque not above the sliding law: T_s at most :data:`ABOVE_SLIDING` times
        the largest torque the model's law gives over the record's speeds (:func:`sliding_peak`)
        holds the bit below the torque it slides at, which is no break-away: it is a torque at rest
        that the regularized law (zero at rest) lacks, a shape of the law such as a Tucker-Wang
        law's c0 tanh(alpha0 v) (1.2 N m from 0.1 rad/s on, docs/loop.md), and the fit lends it the
        effect's name. See :meth:`Effect.flags`.

        Parameters
        ----------
        p : dict
            ``{"static_torque_nm": T_s [N m]}``.
        data : LoopData
            The record (its bit speed over the calibration part).
        model : LoopModel, optional
            The fitted model (its calibrated law and WOB W_0); without it nothing is flagged.
        """
        if model is None or not str(model.law["type"]).startswith("polynomial"):
            return []
        peak = sliding_peak(model, data)
        if p["static_torque_nm"] <= ABOVE_SLIDING * peak:
            return [f"T_s = {p['static_torque_nm']:.3g} N m is not above the sliding law's largest torque "
                    f"({peak:.3g} N m over the record's speeds, x {ABOVE_SLIDING:g}): no break-away, but a torque at "
                    "rest the regularized law lacks (the law's shape)"]
        return []

    def starts(self, model, data):
        """Multiples of the law's torque at the stick threshold: a static torque below it changes
        nothing (the law already holds the bit there): 1.1, 1.4, 1.8 and 2.4 times it. See
        :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            The current model; its law must be polynomial (Eq. 5.1), else ValueError.
        data : LoopData
            The record (its stick threshold [rad/s]).
        """
        self._check(model.law)
        from drillpy.records import identification as ident
        t_low = float(ident.law_eval(model.law, np.array([data.stick_threshold]), np.zeros(1),
                                     np.array([model.wob]))[0][0])
        return [{"static_torque_nm": f * t_low} for f in (1.1, 1.4, 1.8, 2.4)]

    def declared(self, cfg):
        """T_s = gain a0 W / W_ref of a polynomial law with a0 > 0, else None; see
        :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration (its ``law`` and ``operation.wob_n`` W [N]).
        """
        cfg = view(cfg)
        law = cfg.law
        if str(law.type).startswith("polynomial") and float(law.get("a0", 0.0)) > 0:
            return {"static_torque_nm": float(law.gain) * float(law.a0) * float(cfg.operation.wob_n)
                    / float(law.wob_ref_n)}
        return None

    def strip(self, cfg):
        """Set a polynomial law's a0 to 0 (a1 re-tied): the regularized, reversible law, without the
        static torque's ageing (``static_ageing``) either; other laws are left as they are. See
        :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration (its ``law``), modified in place.
        """
        law = cfg["law"]
        if str(law["type"]).startswith("polynomial"):
            self._set(law, 0.0)
            law.pop("static_ageing", None)
            law.pop("static_ageing_s", None)

    @staticmethod
    def _set(law, a0):
        ref = float(law["ref_speed"])
        law["a0"] = float(a0)
        # from a0 at rest to the low-speed piece's value at 1 % of ref (drillpy.records.identification's tie)
        law["a1"] = (float(law["a2"]) + float(law["a3"]) * 0.01 * ref - float(a0)) / (0.01 * ref)

    def configure(self, cfg, p, model):
        """Set the polynomial law's a0 so that its static torque gain a0 W / W_ref is T_s at the
        configuration's WOB (``operation.wob_n``), a1 re-tied; see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration (a polynomial ``law``, else ValueError), modified in place.
        p : dict
            ``{"static_torque_nm": T_s [N m]}``.
        model : LoopModel or None
            Not used.
        """
        self._check(cfg["law"])
        self._set(cfg["law"], _a0(cfg["law"], p["static_torque_nm"], cfg["operation"]["wob_n"]))

    def inject(self, truth, p):
        """Give the truth's (polynomial) law the static torque (:meth:`configure`); see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration).
        p : dict
            ``{"static_torque_nm": T_s [N m]}`` (default 4.5).
        """
        self.configure(truth.cfg, p, None)


EFFECT = StaticFriction()

"""``sensor_gain``: the torque channel's calibration, recorded torque = s T + b."""
from __future__ import annotations

import math

import numpy as np

from .base import Effect, Param

#: s within 1 +- 3 % is no effect: the encoders' torque J a is known to that much (the disk's inertia
#: to about 1 %, the lumped first mode's share of the bar's inertia and the Savitzky-Golay
#: acceleration's amplitude at the cycle's frequency to under 1 % each); the clean independent
#: records give s = 1.002 (docs/loop.md, ``sensor_gain``).
MARGIN = 0.03
#: Largest credible offset [N m]: a load cell's zero drift over a session, about 1 % of a 50 N m
#: cell's span (the rig's torque, 1-3 N m in slip and up to 4.5 N m at a break-away, is read on a
#: cell sized for the motor's torque), i.e. a quarter of the rig's mean torque of about 2 N m.
MAX_OFFSET_NM = 0.5
#: Window [s] of the centred moving average removed from every term of the regression: the twist
#: integrated from the encoders has an unknown offset and drifts with an encoder scale mismatch.
HIGHPASS_S = 2.0


def encoder_torque(model, data) -> dict | None:
    """Regress the recorded torque on the torque the encoders give through the bit's equation.

    The bit's equation of the model's string as one spring and a lumped inertia
    (:func:`drillpy.loop.model.bit_equation`), J a = k phi + c (Omega - v) - T - T_extra, gives the
    true torque on bit from the encoders alone, T = k phi + c (Omega - v) - J a - T_extra (phi the
    twist, the integral of Omega - v). With the recorded torque T_rec = s T + b,

        T_rec = beta_k (k phi) + beta_c (Omega - v) + beta_J (-J a - T_extra) + const,     (SG.1)

    every term high-passed alike (its centred :data:`HIGHPASS_S` moving average removed: the
    twist's offset is unknown, which takes b and the constant with it). The inertial term fixes the
    scale, s = beta_J: the disk's inertia is known and J a is measured by the bit's encoder alone.
    The twist term measures s times the stiffness's ratio to the model's, beta_k / beta_J = GJ /
    GJ_model: a gain scales both terms, a stiffness mismatch (``string_stiffness``) the twist term
    only (the inertial term dominates at the stick-slip transitions, the twist in the stick's
    wind-up). beta_c is free (the calibrated damping need not be the string's). The intervals are
    the least-squares covariance inflated by the residual's autocorrelation time.

    Parameters
    ----------
    model : LoopModel
        The current model (k, J, the torques outside the sensor of its string and effects).
    data : LoopData
        The record on the analysis grid (top speed needed); only its calibration part is used.

    Returns
    -------
    dict or None
        ``scale`` beta_J, ``scale_ci95``, ``gj_ratio`` beta_k / beta_J, ``gj_ratio_ci95``, ``r2``,
        ``n`` samples, ``tau`` autocorrelation time [samples]; None without a top-speed channel or
        with fewer than 10 horizon-lengths of calibration samples.
    """
    if not data.has_top:
        return None
    from scipy.ndimage import uniform_filter1d
    from ..evidence import _autocorrelation_time
    from ..model import bit_equation
    ch, dt = data.ch, data.dt
    eq = bit_equation(model)
    v, a, top = ch["v"], ch["v1"], ch["top"]
    slip = top - v
    phi = np.concatenate([[0.0], np.cumsum(0.5 * (slip[1:] + slip[:-1]) * dt)])
    eps = 0.05 * float(np.mean(np.abs(v)))
    extra = eq["viscous_nms_rad"] * v + eq["string_friction_nm"] * v / np.sqrt(v ** 2 + eps ** 2)
    w = max(3, int(round(HIGHPASS_S / dt)))

    def hp(x):
        return x - uniform_filter1d(x, w, mode="nearest")

    X = np.column_stack([hp(eq["k_nm_rad"] * phi), hp(slip), hp(-eq["J_kg_m2"] * a - extra)])
    y = hp(ch["T"])
    bad = ~(data.valid & data.top_ok)
    bad = np.convolve(bad.astype(float), np.ones(w), mode="full")[: bad.size] > 0  # the integral carries it
    keep = ~bad & (data.t < data.t_split)
    keep[: w // 2] = keep[-(w // 2):] = False  # the moving average's edges
    if keep.sum() < 10 * data.L:
        return None
    X, y = X[keep], y[keep]
    beta, *_ = np.linalg.lstsq(X, y, rcond=None)
    r = y - X @ beta
    tau = _autocorrelation_time(r)
    cov = np.linalg.inv(X.T @ X) * float(np.var(r, ddof=3)) * tau
    bk, bj = float(beta[0]), float(beta[2])
    # the ratio's variance by the delta method
    var_ratio = (cov[0, 0] / bj ** 2 - 2 * bk * cov[0, 2] / bj ** 3 + bk ** 2 * cov[2, 2] / bj ** 4)
    hs, hr = 1.96 * math.sqrt(cov[2, 2]), 1.96 * math.sqrt(max(var_ratio, 0.0))
    return {"scale": bj, "scale_ci95": [bj - hs, bj + hs], "gj_ratio": bk / bj,
            "gj_ratio_ci95": [bk / bj - hr, bk / bj + hr], "r2": float(1.0 - np.var(r) / np.var(y)),
            "n": int(y.size), "tau": float(tau)}


class SensorGain(Effect):
    """The torque channel's calibration: the load cell records, of the true torque on bit T,

        T_rec = s T + b.                                                                   (SG.0)

    The model's state, its law residual and its restart torque take
    (T_rec - b) / s, its predicted torque is compared with the record as s T_pred + b
    (:meth:`torque_sensor`, :func:`drillpy.loop.model.torque_sensor`).

    Parameters ``torque_scale`` s [-] (0.8-1.25; absent at 1 within +-:data:`MARGIN`) and
    ``torque_offset_nm`` b [N m] (+-:data:`MAX_OFFSET_NM`).

    Identifiable only through the dynamics: without the effect the law absorbs both (a law s T_law
    + b fits the law residual as well), but the torque's scale is pinned by the disk's inertia and
    the bar's stiffness, which relate it to the encoders' speeds. **Measured directly**
    (:meth:`direct`, :func:`encoder_torque`): s from the inertial term of the bit's equation,
    significant when its interval excludes 1 +- :data:`MARGIN` and the twist term agrees (a
    stiffness ratio within the GJ's margin of 1: otherwise the mismatch is the stiffness's, and the
    candidate is not proposed). s is then held at the measured value. The offset b is *not*
    identifiable through the torsional dynamics: a constant torque in the record is a constant twist
    in the restart state and a constant in the law, which predict the same motion; only the law's
    scaling with the WOB (b does not scale) separates it, and not at all in a model at a constant
    WOB. Fitted on the short horizons it wandered with the law's constant a4 (-0.03 N m on the
    candidate, 0.44 N m on its refit, on a record read with b = 0.15 N m), each with an interval
    of +-0.006 N m that ignored the other: the loop therefore holds b (0 unless a model declares
    it), the law carrying the offset, and reports it as not identified.
    """
    name = "sensor_gain"
    params = (Param("torque_scale", "-", "s: the torque channel reads s T + b of the true torque T", 0.8, 1.25,
                    null=1.0, margin=MARGIN),
              Param("torque_offset_nm", "N m", "b: the torque channel's zero offset (reads s T + b; not identified "
                    "through the dynamics: the law carries it)", -MAX_OFFSET_NM, MAX_OFFSET_NM, fitted=False))
    change = ("the recorded torque is s T + b of the model's torque T: the state, the law residual and the restarts "
              "take (T_rec - b) / s, the predictions are compared as s T_pred + b")
    signature = ("the recorded torque does not balance the bit's equation from the encoders, J a = k phi + c (Omega - v) "
                 "- T, by a factor: the law absorbs it, so the predicted accelerations are off by s over every slip")
    reading = ("a torque load cell's calibration: a gain set for another cell or bridge voltage, a zero that drifted "
               "with temperature or a re-tightened clamp")
    needs = ("top_speed",)
    defaults = {"torque_scale": 1.15, "torque_offset_nm": 0.15}

    def free(self, p):
        """None when s was measured from the encoders (``p["source"] == "encoders"``: s is held),
        else s (b is never fitted); see :meth:`Effect.free`.

        Parameters
        ----------
        p : dict
            ``{"torque_scale": s, "torque_offset_nm": b [N m]}``, possibly with ``"source"``.
        """
        return () if p.get("source") == "encoders" else self.params[:1]

    def starts(self, model, data):
        """s of 0.9, 1.1 and 1.2 with b = 0; see :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            Not used.
        data : LoopData
            Not used.
        """
        return [{"torque_scale": s, "torque_offset_nm": 0.0} for s in (0.9, 1.1, 1.2)]

    def direct(self, model, data):
        """s from the encoders (:func:`encoder_torque`, Eq. SG.1), b held at 0; significant when
        the interval of s excludes 1 +- :data:`MARGIN` and the stiffness ratio's interval reaches
        1 +- the GJ's margin; see :meth:`Effect.direct`.

        Parameters
        ----------
        model : LoopModel
            The current model (without the effect).
        data : LoopData
            The record on the analysis grid; only its calibration part is used.

        Returns
        -------
        dict or None
            ``params`` ``{"torque_scale": s, "torque_offset_nm": 0, "source": "encoders"}``, the
            interval of s, ``significant`` and ``detail``; None without a top-speed channel.
        """
        from .string_stiffness import MARGIN as GJ_MARGIN
        m = encoder_torque(model, data)
        if m is None:
            return None
        s, (lo, hi) = m["scale"], m["scale_ci95"]
        g, (glo, ghi) = m["gj_ratio"], m["gj_ratio_ci95"]
        gain = lo > 1.0 + MARGIN or hi < 1.0 - MARGIN
        stiff_ok = glo <= 1.0 + GJ_MARGIN and ghi >= 1.0 - GJ_MARGIN
        return {"params": {"torque_scale": min(max(s, 0.8), 1.25), "torque_offset_nm": 0.0, "source": "encoders"},
                "ci95": {"torque_scale": [lo, hi]}, "significant": bool(gain and stiff_ok),
                "detail": f"torque scale {s:.4f} [{lo:.4f}, {hi:.4f}] from the encoders' inertial term, twist's "
                          f"stiffness ratio {g:.4f} [{glo:.4f}, {ghi:.4f}] (R^2 {m['r2']:.3f}, {m['n']} samples)"}

    def torque_sensor(self, p):
        """(s, b); see :meth:`Effect.torque_sensor`.

        Parameters
        ----------
        p : dict
            ``{"torque_scale": s, "torque_offset_nm": b [N m]}``.
        """
        return float(p["torque_scale"]), float(p["torque_offset_nm"])

    def measure(self, p, chans, fs):
        """The simulated torque as the load cell records it, s T + b; see :meth:`Effect.measure`.

        Parameters
        ----------
        p : dict
            ``{"torque_scale": s, "torque_offset_nm": b [N m]}``.
        chans : dict
            Simulated channels, name -> 1-D array.
        fs : float
            Not used.
        """
        s, b = self.torque_sensor(p)
        return {**chans, "torque_on_bit": s * np.asarray(chans["torque_on_bit"]) + b}

    def inject(self, truth, p):
        """Append s T + b on the torque channel to the truth's measurement functions; see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its ``post`` list).
        p : dict
            ``{"torque_scale": s, "torque_offset_nm": b [N m]}`` (defaults 1.15 and 0.15).
        """
        truth.post.append(lambda chans, fs: self.measure(p, chans, fs))


EFFECT = SensorGain()

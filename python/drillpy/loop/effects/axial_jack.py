"""``axial_jack``: the weight on bit is a state of the rig, not a constant or an input."""
from __future__ import annotations

import numpy as np

from drillpy.records.rigsim import RIG_PARAMETERS

from .base import Effect, Param
from ..view import view

_G, _TAU = RIG_PARAMETERS["jack_gain_n_rad"], RIG_PARAMETERS["jack_relaxation_s"]


class AxialJack(Effect):
    """The rig's electrical jack: the WOB a state of the model (``drill/axial.hpp``),

        W' = g (Omega_f - v) - (W - W_s(t)) / tau,   W >= 0,

    the jack's feed compressing the axial compliance while the bit lags its steady rotation Omega_f
    and relieving it while the bit runs ahead, relaxed towards the set force W_s(t) (the law's WOB
    input: the recorded WOB's trend below 0.5 Hz where the record shows the WOB is a response,
    :func:`drillpy.loop.data.wob_response`) on the jack's time scale tau. The law takes this W.

    Parameters ``gain_n_rad`` g [N/rad] (WOB per radian of lag: the axial stiffness times the depth of
    cut per revolution over 2 pi; 1-1000) and ``relaxation_s`` tau [s] (0.02-3), the ranges of the
    whole-rig model (:data:`drillpy.records.rigsim.RIG_PARAMETERS`, with their sources). The restarts start
    the state at the recorded WOB (:meth:`restart_wob`). Needs a WOB channel, and is a candidate only
    where the record's WOB is a response of the rotation (:meth:`applicable`). The horizons of a model
    with it run in SIMD lockstep like the others, the jack's WOB a state of each lane (issue 33;
    ``--scalar``: the scalar integrator, the same decisions).
    """
    name = "axial_jack"
    # the ranges of the whole-rig model (drillpy.records.rigsim.RIG_PARAMETERS, with their sources); the
    # gain fitted in ln from 1 N/rad
    params = (Param("gain_n_rad", "N/rad", "g: WOB gained per radian the bit lags its steady rotation",
                    max(_G[0], 1.0), _G[1], "log"),
              Param("relaxation_s", "s", "tau: time constant of the jack's return to its set force", _TAU[0], _TAU[1],
                    "log"))
    change = ("W' = g (Omega_f - v) - (W - W_s) / tau, the WOB a state (drill/axial.hpp) started at the recorded WOB; "
              "the law takes it")
    signature = ("a torque residual that follows the bit's angle deficit: the torque rises while the bit is stuck "
                 "beyond what the law at the set WOB gives, and falls in slip")
    reading = ("the electrical jack feeds the rock holder at a steady rate while the bit removes rock as it turns: the "
               "WOB rises while the bit sticks and falls while it slips (section 5.3.2, Figs. 5.6-5.7)")
    needs = ("wob",)
    wob_state = True
    defaults = {"gain_n_rad": 130.0, "relaxation_s": 0.1}

    def starts(self, model, data):
        """The gain the record's WOB shows per radian of the bit's angle deficit
        (``data.wob_response["gain_n_rad"]`` when between 2 and 500 N/rad, else 130 N/rad, sample
        175's order) at half, once and twice its value, each with tau of 0.05 s and 0.3 s; see
        :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            Not used.
        data : LoopData
            The record (its :func:`~drillpy.loop.data.wob_response`).
        """
        wr = data.wob_response or {}
        g = float(wr.get("gain_n_rad", 0.0))
        g = g if 2.0 < g < 500.0 else self.defaults["gain_n_rad"]
        return [{"gain_n_rad": f * g, "relaxation_s": tau} for f in (0.5, 1.0, 2.0) for tau in (0.05, 0.3)]

    def applicable(self, data):
        """Only where the record's WOB is a response of the rotation
        (:func:`drillpy.loop.data.wob_response`): an exogenous WOB has no jack to model, and the
        jack relaxed fast towards it would only stand in for ``wob_coupling``; see
        :meth:`Effect.applicable`.

        Parameters
        ----------
        data : LoopData
            The record (its ``wob_response``).
        """
        return bool(data.wob_response and data.wob_response["response"])

    def declared(self, cfg):
        """``cfg.axial`` when it is a jack (its ``gain_n_rad`` and ``relaxation_s``), else None;
        see :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration.
        """
        ax = view(cfg).axial
        if ax.type != "jack":
            return None
        return {"gain_n_rad": float(ax.gain_n_rad), "relaxation_s": float(ax.relaxation_s)}

    def strip(self, cfg):
        """Remove ``axial`` (the WOB the law's input again); see :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        """
        cfg.pop("axial", None)

    def configure(self, cfg, p, model):
        """``axial: {"type": "jack", "gain_n_rad": g, "relaxation_s": tau}``; see
        :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            ``{"gain_n_rad": g [N/rad], "relaxation_s": tau [s]}``.
        model : LoopModel or None
            Not used.
        """
        cfg["axial"] = {"type": "jack", "gain_n_rad": float(p["gain_n_rad"]), "relaxation_s": float(p["relaxation_s"])}

    def wob_input(self, p, model, w):
        """The jack's set force W_s(t) [N]: the recorded WOB as the loop gives it to the law (its
        trend where the WOB is a response); see :meth:`Effect.wob_input`.

        Parameters
        ----------
        p : dict
            Not read.
        model : LoopModel
            Not used.
        w : numpy.ndarray or None
            The law's WOB channel [N] per sample; None returns None.
        """
        return None if w is None else np.asarray(w, float)

    def restart_wob(self, p, model, data, chs, idx):
        """The recorded WOB [N] at the restarts (``data.wob_measured`` where the law takes the
        trend, else the WOB channel); see :meth:`Effect.restart_wob`.

        Parameters
        ----------
        p : dict
            Not read.
        model : LoopModel
            Not used.
        data : LoopData
            The record on the analysis grid.
        chs : dict
            State channels (``W`` [N]).
        idx : array_like of int
            Restart sample indices.
        """
        w = data.wob_measured if data.wob_measured is not None else chs["W"]
        return np.asarray(w, float)[np.asarray(idx)]

    def inject(self, truth, p):
        """Give the truth the jack (``axial``); its recorded WOB is then the state
        (:func:`drillpy.loop.synthetic.synthetic_record`); see :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its configuration replaced by a changed copy).
        p : dict
            ``{"gain_n_rad": g [N/rad], "relaxation_s": tau [s]}`` (defaults 130 and 0.1).
        """
        truth.cfg = view(truth.cfg).replace(axial={"type": "jack", "gain_n_rad": float(p["gain_n_rad"]),
                                                   "relaxation_s": float(p["relaxation_s"])}).to_dict()


EFFECT = AxialJack()

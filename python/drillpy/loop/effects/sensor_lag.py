"""``sensor_lag``: the recorded channels went through a low-pass the model does not have."""
from __future__ import annotations

import math

from .base import Effect, Param
from ..view import view

SQRT2 = math.sqrt(2.0)
#: Highest credible cutoff [Hz]: an acquisition filter sits above the dynamics of interest; above 30 Hz
#: its group delay (< 7.5 ms) is under 3 % of a 0.25 s horizon and it barely changes a 2.9 Hz rig's signals.
MAX_CUTOFF_HZ = 30.0


class SensorLag(Effect):
    """The recorded channels went through a second-order Butterworth low-pass the model does not
    have, y'' + sqrt(2) omega_c y' + omega_c^2 y = omega_c^2 x (``drill/sensor.hpp``).

    Parameter ``lowpass_hz`` f_c [Hz] (1 to :data:`MAX_CUTOFF_HZ`, fitted in ln; no finite
    no-effect value). The model's outputs pass through the filter, its restart state is read
    sqrt(2) / omega_c later on the record and the law residual is formed with the filter undone.
    """
    name = "sensor_lag"
    params = (Param("lowpass_hz", "Hz", "cutoff f_c of a second-order Butterworth low-pass", 1.0, MAX_CUTOFF_HZ, "log"),)
    change = ("the model's outputs through y'' + sqrt(2) omega_c y' + omega_c^2 y = omega_c^2 x (drill/sensor.hpp), "
              "its state from the channels with the filter undone")
    signature = ("residuals early in every horizon, where the recorded channels lag and round off what the model "
                 "predicts from a state read off lagged channels (sharpest at the stick-slip transitions)")
    reading = ("the acquisition's second-order IIR low-pass at 10 Hz on every channel, encoders included "
               "(section 5.3.1), put there against the platform's 20 Hz mode")
    defaults = {"lowpass_hz": 10.0}

    def describe(self, p):
        """The cut-off and the group delay sqrt(2) / w_c; see :meth:`Effect.describe`.

        Parameters
        ----------
        p : dict
            The effect's values (``lowpass_hz``).
        """
        fc = p["lowpass_hz"]
        return (f"the recorded channels went through a low-pass at {fc:.3g} Hz (group delay "
                f"{1e3 * math.sqrt(2) / (2 * math.pi * fc):.1f} ms)")

    def starts(self, model, data):
        """Cutoffs 2, 4, 8 and 16 Hz; see :meth:`Effect.starts`.

        Parameters
        ----------
        model : LoopModel
            Not used.
        data : LoopData
            Not used.
        """
        return [{"lowpass_hz": f} for f in (2.0, 4.0, 8.0, 16.0)]

    def flags(self, p, data, model=None):
        """Flag a filter whose delay sqrt(2) / omega_c is under two analysis samples: it cannot move
        a prediction of the horizon's length; see :meth:`Effect.flags`.

        Parameters
        ----------
        p : dict
            ``{"lowpass_hz": f_c [Hz]}``.
        data : LoopData
            The record (its sampling interval ``dt`` [s] and horizon length ``L`` [samples]).
        model : LoopModel, optional
            Not used.
        """
        d = self.delay_s(p)
        if d < 2.0 * data.dt:
            return [f"a {p['lowpass_hz']:.3g} Hz filter delays the channels by {1e3 * d:.2f} ms, under two analysis "
                    f"samples ({1e3 * data.dt:.2f} ms): it cannot move a {data.L * data.dt:g} s prediction"]
        return []

    def declared(self, cfg):
        """``{"lowpass_hz"}`` of ``cfg.sensors`` when it is > 0, else None; see
        :meth:`Effect.declared`.

        Parameters
        ----------
        cfg : dict or Configuration
            The declared engine configuration.
        """
        sensors = view(cfg).get("sensors")
        fc = 0.0 if sensors is None else float(sensors.get("lowpass_hz", 0.0))
        return {"lowpass_hz": fc} if fc > 0 else None

    def strip(self, cfg):
        """Remove ``sensors`` (ideal sensors); see :meth:`Effect.strip`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        """
        cfg.pop("sensors", None)

    def configure(self, cfg, p, model):
        """Set ``cfg["sensors"] = {"lowpass_hz": f_c}``; see :meth:`Effect.configure`.

        Parameters
        ----------
        cfg : dict
            Engine configuration, modified in place.
        p : dict
            ``{"lowpass_hz": f_c [Hz]}``.
        model : LoopModel or None
            Not used.
        """
        cfg["sensors"] = {"lowpass_hz": float(p["lowpass_hz"])}

    def delay_s(self, p):
        """Low-frequency group delay sqrt(2) / omega_c [s], omega_c = 2 pi f_c; see
        :meth:`Effect.delay_s`.

        Parameters
        ----------
        p : dict
            ``{"lowpass_hz": f_c [Hz]}``.

        Returns
        -------
        float
            The delay [s] (e.g. 22.5 ms at 10 Hz).
        """
        return SQRT2 / (2 * math.pi * p["lowpass_hz"])

    def undo(self, p):
        """The filter's inverse x = y + (sqrt(2) / omega_c) y' + (1 / omega_c^2) y''; see
        :meth:`Effect.undo`.

        Parameters
        ----------
        p : dict
            ``{"lowpass_hz": f_c [Hz]}``.

        Returns
        -------
        tuple of float
            (sqrt(2) / omega_c [s], 1 / omega_c^2 [s^2]).
        """
        w = 2 * math.pi * p["lowpass_hz"]
        return SQRT2 / w, 1.0 / w ** 2

    def measure(self, p, chans, fs):
        """Every channel through the engine's own filter (``_core.lowpass2``, ``drill/sensor.hpp``);
        see :meth:`Effect.measure`.

        Parameters
        ----------
        p : dict
            ``{"lowpass_hz": f_c [Hz]}``.
        chans : dict
            Simulated channels, name -> 1-D array.
        fs : float
            Their sampling rate [Hz].
        """
        from drillpy import _core  # the engine's measurement chain (drill/sensor.hpp)
        return {k: _core.lowpass2(x, p["lowpass_hz"], 1.0 / fs) for k, x in chans.items()}

    def inject(self, truth, p):
        """Append SciPy's Butterworth (:func:`drillpy.records.signals.rig_lowpass`, an
        implementation independent of the engine's) to the truth's measurement functions; see
        :meth:`Effect.inject`.

        Parameters
        ----------
        truth : drillpy.loop.synthetic.Truth
            The synthetic truth (its ``post`` list).
        p : dict
            ``{"lowpass_hz": f_c [Hz]}`` (default 10, the rig's acquisition filter).
        """
        # the truth's acquisition filter is an independent implementation (SciPy's bilinear Butterworth)
        from drillpy.records.signals import rig_lowpass
        truth.post.append(lambda chans, fs: {k: rig_lowpass(x, fs, cutoff_hz=p["lowpass_hz"])
                                             for k, x in chans.items()})


EFFECT = SensorLag()

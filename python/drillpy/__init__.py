"""drillpy: torsional dynamics of oil-well drill strings under uncertainty.

The numerics run in the C++ engine (``drillpy._core``); this package adds configuration
handling, progress bars, figures, reports and the ``drillpy`` command.

The names below are imported on first use (PEP 562), so that ``import drillpy`` and
``drillpy --help`` do not load SciPy and Matplotlib: ``drillpy.simulate`` is
:func:`drillpy.model.simulation.simulate`, and so on.
"""
from __future__ import annotations

import importlib

from . import _core

__version__ = "0.1.0"

#: public name -> the module that defines it
_EXPORTS = {
    **dict.fromkeys(("load_config", "preset_names", "with_overrides"), "drillpy.model.config"),
    "Configuration": "drillpy.model.configuration",
    **dict.fromkeys(("SimulationResult", "natural_frequencies", "simulate", "stability_map", "sweep_severity",
                     "severity_threshold", "severity_crossings", "law_torque"), "drillpy.model.simulation"),
    **dict.fromkeys(("FRFEnvelope", "cb_frequencies", "dispersions", "frf_envelope", "stochastic_model"),
                    "drillpy.uncertainty.frf"),
    **dict.fromkeys(("SeverityStudy", "severity_sources", "severity_study"), "drillpy.uncertainty.structural"),
    **dict.fromkeys(("PsdModel", "PsdTable", "THESIS_PSD", "generate", "periodogram", "welch", "fit_psd_model",
                     "fit_eta"), "drillpy.uncertainty.process"),
    **dict.fromkeys(("StochasticStudy", "PhaseStudy", "stochastic_study", "phase_study", "conv1"),
                    "drillpy.uncertainty.montecarlo"),
    **dict.fromkeys(("Record", "read_record", "write_csv"), "drillpy.records.io"),
    "clean": "drillpy.records.cleaning",
    **dict.fromkeys(("LoopOptions", "run_loop"), "drillpy.loop"),
    "loop_record": "drillpy.reports.loop",
    "synthetic_record": "drillpy.loop.synthetic",
    **dict.fromkeys(("Study", "run_study", "compute_study", "open_study"), "drillpy.study"),
}

__all__ = ["_core", "__version__", *_EXPORTS]


def __getattr__(name: str):
    """Import a public name's module on first use (PEP 562).

    Parameters
    ----------
    name : str
        The attribute asked for.

    Returns
    -------
    object
        The public function, class or constant.

    Raises
    ------
    AttributeError
        For a name drillpy does not export.
    """
    module = _EXPORTS.get(name)
    if module is None:
        raise AttributeError(f"module 'drillpy' has no attribute {name!r}")
    value = getattr(importlib.import_module(module), name)
    globals()[name] = value
    return value


def __dir__() -> list:
    """Every public name, imported or not yet."""
    return sorted(set(globals()) | set(_EXPORTS))

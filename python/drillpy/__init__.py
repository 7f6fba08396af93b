"""drillpy: torsional dynamics of oil-well drill strings under uncertainty.

The numerics run in the C++ engine (``drillpy._core``); this package adds configuration
handling, progress bars, figures, reports and the ``drillpy`` command.
"""
from . import _core
from drillpy.model.config import load_config, preset_names, with_overrides
from drillpy.model.simulation import (SimulationResult, natural_frequencies, simulate, stability_map,
                         sweep_severity, severity_threshold, law_torque)
from drillpy.uncertainty.frf import FRFEnvelope, cb_frequencies, dispersions, frf_envelope, stochastic_model
from drillpy.uncertainty.structural import SeverityStudy, severity_sources, severity_study
from drillpy.uncertainty.process import (PsdModel, PsdTable, THESIS_PSD, generate, periodogram, welch, fit_psd_model,
                      fit_eta)
from drillpy.uncertainty.montecarlo import StochasticStudy, PhaseStudy, stochastic_study, phase_study, conv1

__all__ = [
    "load_config", "preset_names", "with_overrides", "SimulationResult", "natural_frequencies",
    "simulate", "stability_map", "sweep_severity", "severity_threshold", "law_torque", "_core",
    "FRFEnvelope", "cb_frequencies", "dispersions", "frf_envelope", "stochastic_model",
    "SeverityStudy", "severity_sources", "severity_study",
    "PsdModel", "PsdTable", "THESIS_PSD", "generate", "periodogram", "welch", "fit_psd_model",
    "fit_eta", "StochasticStudy", "PhaseStudy", "stochastic_study", "phase_study", "conv1",
]
# measured records (issue 5); analysis, identification and rigsim are imported on demand
from drillpy.records.io import Record, read_record, write_csv  # noqa: E402
from drillpy.records.cleaning import clean  # noqa: E402

__all__ += ["Record", "read_record", "write_csv", "clean"]
# drillpy loop: residual -> missing effect -> corrected model (issue 6)
from .loop import LoopOptions, run_loop, loop_record  # noqa: E402
from drillpy.records.synthetic import synthetic_record  # noqa: E402

__all__ += ["LoopOptions", "run_loop", "loop_record", "synthetic_record"]
__version__ = "0.1.0"

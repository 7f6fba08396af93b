"""Every figure, one module per area (Agg backend: files only). Figures take the result objects
that the compute functions return; none of them computes a study.

Naming: a ``*_plot`` function draws one figure, writes one PNG (unless its path is None) and returns its matplotlib Figure; a
``*_figures`` function draws every figure of one result object into an output folder:

* :mod:`~drillpy.figures.simulation`: deterministic runs (time series, SS curves, stability maps);
* :mod:`~drillpy.figures.stochastic`: chapter 4, :func:`~drillpy.figures.stochastic.stochastic_figures`
  of a :class:`drillpy.uncertainty.stochastic.StochasticAnalysis`;
* :mod:`~drillpy.figures.frf`: chapter 6 and appendix C, :func:`~drillpy.figures.frf.chapter6_figures`
  of a :class:`drillpy.uncertainty.chapter6.Chapter6Study`;
* :mod:`~drillpy.figures.records`: measured records, :func:`~drillpy.figures.records.analysis_figures`
  of a :class:`drillpy.records.analysis.RecordAnalysis`;
* :mod:`~drillpy.figures.loop`: ``drillpy loop``, :func:`~drillpy.figures.loop.loop_figures` of a
  :class:`drillpy.loop.LoopResult`.
"""

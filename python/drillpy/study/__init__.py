"""Studies past one machine: a study is a grid of independent tasks computed on a backend (OpenMP
in this process, or Dask distributed) and stored as a labelled Zarr store that resumes and extends.

* :mod:`drillpy.study.definition` -- :class:`Study` (sweep, map, mc), :func:`mc_study` and one block's computation;
* :mod:`drillpy.study.store` -- ``DIR/study.zarr`` (zarr alone; xarray labels it on demand): the done
  flags, resume and extend;
* :mod:`drillpy.study.run` -- :func:`run_study` (labelled) and :func:`compute_study` (numpy) on the
  ``local`` or ``dask`` backend;
* :mod:`drillpy.study.cluster` -- the ``--scheduler`` option and its Dask client (the calibration's too).
"""
from drillpy.study.definition import Study, mc_study
from drillpy.study.run import compute_study, run_study
from drillpy.study.store import open_study

__all__ = ["Study", "mc_study", "run_study", "compute_study", "open_study"]

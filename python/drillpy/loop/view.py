"""A configuration the loop holds as a dict (a model's ``cfg``, a trial's engine configuration, a
synthetic truth's), read by attribute without a copy."""
from __future__ import annotations

from drillpy.model.configuration import Configuration


def view(cfg) -> Configuration:
    """A read-only :class:`~drillpy.model.configuration.Configuration` over ``cfg`` (not copied, unlike
    :meth:`Configuration.of <drillpy.model.configuration.Configuration.of>`): for reading a dict the loop
    owns and edits in place at its edges (``LoopModel.cfg``, ``Effect.configure``, ``Effect.strip``),
    read before the next edit.

    Parameters
    ----------
    cfg : dict or Configuration
        A configuration (a Configuration is returned as is).

    Returns
    -------
    Configuration
        Reading the same dict: an edit of ``cfg`` shows through.
    """
    return cfg if isinstance(cfg, Configuration) else Configuration._owning(cfg)

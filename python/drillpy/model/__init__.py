"""The deterministic model: configurations and presets (shared with ``drillsim``), single runs,
sweeps and stability maps, and the convergence studies of its discretization (thesis chapters 2-3)."""

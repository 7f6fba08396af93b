"""Bayesian calibration of the rig model from a record (issue 35): priors from physical ranges
(:mod:`.priors`), summary statistics that carry the stick-slip cycle (:mod:`.summaries`), a
population Monte Carlo ABC-SMC over the model and its parameters (:mod:`.abcsmc`) and the rig
model's posterior with its predictive intervals (:mod:`.posterior`)."""

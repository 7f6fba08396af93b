"""Measured records: reading and writing, artifact cleaning, signal analysis, identification of
the bit-rock laws, the test rig in simulation, statistics across records, predictions of a
calibrated model and synthetic records (thesis chapter 5)."""

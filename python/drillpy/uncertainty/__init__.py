"""Uncertainty: the random torque fluctuation of the bit-rock law and its Monte Carlo studies
(thesis chapter 4), the robust speed, and the random structure in the frequency and time domains
(chapter 6, appendix C)."""

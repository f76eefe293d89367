"""LS-DYNA keyword decks: every virtual test written as a complete deck (in-lbf-s, m-N-s or
mm-N-ms), and decks with the supported keywords read back and run. Above the lab tests, whose
setups it translates.
"""

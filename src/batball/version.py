"""The package version: one home, read by packaging (pyproject's dynamic version), by run keys
and by exported decks, at the bottom of the layers so any module may import it."""

__version__ = "0.1.3"

"""Settings shared by every Numba kernel."""

from __future__ import annotations

#: Fast-math flags that keep NaN and infinity semantics, so failure checks still see them.
FASTMATH = {"nsz", "arcp", "contract", "afn", "reassoc"}

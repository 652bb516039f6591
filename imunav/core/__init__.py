"""Layer 0 — the vocabulary every other layer uses: constants and unit tables, input checks and
the one error type, rotations, and the one state type.

May import: nothing in imunav outside ``imunav.core``.
"""

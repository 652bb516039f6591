"""SymPy derivations behind the paper reproductions (importable, tested, printed by notebooks).

May import: nothing from imunav but ``imunav.symbolic``.
"""

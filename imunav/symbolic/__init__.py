"""SymPy derivations behind the paper reproductions (importable, tested, printed by notebooks)."""

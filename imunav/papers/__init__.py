"""One module per source paper; each converts the paper's conventions at its boundary.

May import: anything below the papers, and ``imunav.symbolic``; only the reproduce registry and
the command line import the papers.
"""

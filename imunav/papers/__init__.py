"""One module per source paper; each converts the paper's conventions at its boundary."""

"""Files: sample tables in, reductions and reports out (every writer atomic)."""

"""Layer 7 — the ``metro`` command: argument parsing, terminal presentation, the register
commands, ``metro doctor`` and batches of lots (Dask).
"""

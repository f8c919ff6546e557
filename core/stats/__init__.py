"""Layer 2 — pure formula functions on arrays: Allan statistics (:mod:`allan`: the deviations,
with :mod:`allan_base`, :mod:`allan_edf`, :mod:`allan_blocks` and the compiled
:mod:`allan_kernels`), least squares, sine fits, settling, signal helpers and the earth's rate.
Each cites its clause and equation; no units conversion and no I/O here.
"""

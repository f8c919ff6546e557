"""Layer 2 — pure formula functions on arrays: Allan statistics, least squares, sine fits,
settling, signal helpers and the earth's rate.  Each cites its clause and equation; no units
conversion and no I/O here.
"""

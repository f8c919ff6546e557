"""Layer 1 — the foundation every other layer stands on: errors, units (one pint registry),
the manifest vocabulary, messages and their translations (locale), number formatting, atomic
file writes, optional extras and option parsing.  Imports nothing else of metro.
"""

"""Layer 5 — documents: the report context, the Word/PDF builder, figures and their cache,
notes.  Beside :mod:`metro.core.run` (neither imports the other).
"""

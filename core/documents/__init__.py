"""Layer 5 — documents.  Beside :mod:`metro.core.run` (neither imports the other).

From the bottom up: :mod:`~metro.core.documents.text` (page geometry, subscripts, no-break
spaces, column widths, quantity names) and :mod:`~metro.core.documents.notes`;
:mod:`~metro.core.documents.context` (a run record as a report context: plain strings, lists
and dicts); :mod:`~metro.core.documents.builder` (the one Word builder) and
:mod:`~metro.core.documents.pdf` (LibreOffice); :mod:`~metro.core.documents.document` (the
sections every document shares, the generic layout); :mod:`~metro.core.documents.plots` and
:mod:`~metro.core.documents.figure_cache` (figures); :mod:`~metro.core.documents.report`
(writing a context as a document, atomically).
"""

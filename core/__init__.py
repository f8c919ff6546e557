"""metro core, in layers (docs/architecture.md): base → stats → uncertainty → model →
run | documents → record → cli, each importing only those below it (``.importlinter``).

A plugin imports ``metro.api``, never this package.  Inside metro, import the pieces from
their modules (``metro.core.uncertainty.budget``, ``metro.core.model.results``, …); this package
only exposes the hook marker and the version, so ``import metro.core`` stays cheap.
"""

from __future__ import annotations

from importlib import metadata as _md

import pluggy as _pluggy

from .base.extras import DISTRIBUTION as _DISTRIBUTION  # the name on the package index

hookimpl = _pluggy.HookimplMarker("metro")

try:
    __version__ = _md.version(_DISTRIBUTION)
except _md.PackageNotFoundError:  # pragma: no cover - running from a bare checkout
    __version__ = "0+unknown"

__all__ = ["hookimpl", "__version__"]

"""Shared fixtures: a plugin manager without autoload, and a small simulated campaign."""

from __future__ import annotations

import pytest


@pytest.fixture
def pm():
    """metro's plugin manager with only the built-in plugins (no third-party autoload)."""
    from metro.core.plugins import get_plugin_manager

    return get_plugin_manager(autoload=False)

"""Layer 5 — running items: the plugin manager, reading and writing a campaign's manifest,
the runner that evaluates items, output-path checks and the pytest fixtures for plugin authors.
"""

"""ACME Inertial's metro plugin (an example third-party distribution)."""

__version__ = "0.1.0"

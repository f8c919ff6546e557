"""Optional dependencies ("extras") and the one message a missing one gives.

The core install (``pip install metro-inertial``) is what one station needs: acquire, run,
reports, the register on SQLite.  The rest comes with extras:

=============  ==========================  ==============================================
extra          brings                      for
=============  ==========================  ==============================================
``fast``       numba, pyarrow              compiled Allan kernels, the multi-threaded CSV
                                           reader and writer, Parquet sample files
``batch``      dask[distributed], pyarrow  ``metro batch`` (a production lot on a cluster)
``postgres``   psycopg[binary]             a register shared by several stations
``drivers``    pyvisa, pyserial            live instrument drivers
``dcc``        xmlschema                   checking a DCC against its schema (importing an
                                           equipment's DCC; docs/dcc.md)
``web``        starlette, jinja2, uvicorn  ``metro serve`` (the register in a browser)
``all``        all of the above
=============  ==========================  ==============================================

Code that needs one of them calls :func:`require`, which imports the module or raises
:class:`~metro.core.base.errors.MetroError` (exit 2) naming the extra to install.  Code with a
fallback (the numpy CSV reader, the numpy Allan engine) calls :func:`available` instead.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from types import ModuleType

from .errors import MetroError

#: The distribution name on the package index (the command and the import name are ``metro``).
DISTRIBUTION = "metro-inertial"

#: module -> the extra that installs it
EXTRA_OF = {
    "numba": "fast",
    "pyarrow": "fast",
    "distributed": "batch",
    "dask": "batch",
    "psycopg": "postgres",
    "xmlschema": "dcc",
    "starlette": "web",
    "uvicorn": "web",
}


def install_line(extra: str) -> str:
    """The pip command that installs ``extra``."""
    return f"pip install '{DISTRIBUTION}[{extra}]'"


def available(module: str) -> bool:
    """True when ``module`` can be imported (without importing it)."""
    try:
        return importlib.util.find_spec(module) is not None
    except (ImportError, ValueError):
        return False


def require(module: str, what: str, *, extra: str | None = None) -> ModuleType:
    """Import ``module`` for ``what`` (e.g. "metro batch"), or say which extra to install.

    Raises MetroError: "metro batch needs the 'batch' extra: pip install 'metro-inertial[batch]'".
    """
    extra = extra or EXTRA_OF[module.split(".")[0]]
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        missing = getattr(exc, "name", None) or module
        raise MetroError(
            f"{what} needs the '{extra}' extra: {install_line(extra)}",
            hint=f"{missing} is not installed in the environment metro runs from ({sys.prefix}); "
            "run that pip line with this environment's pip",
        ) from None

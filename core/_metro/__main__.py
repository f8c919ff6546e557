"""``python -m metro``: the ``metro`` command (setup.py maps this folder onto the ``metro``
namespace itself, so the namespace gets a ``__main__`` without becoming a regular package)."""

import sys

from metro.core.cli.app import main

sys.exit(main())

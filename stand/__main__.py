"""``python -m stand``: the ``stand`` command line."""
import sys

from .cli import main

sys.exit(main())

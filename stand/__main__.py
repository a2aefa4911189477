"""``python -m stand``: the ``stand`` command line."""
import sys

from stand.cli import main

sys.exit(main())

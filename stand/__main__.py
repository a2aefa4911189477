"""``python -m stand``: the ``stand`` command line."""
import sys

from stand.cli.main import main

sys.exit(main())

"""The ``stand`` command line: :mod:`.parser` (commands and their arguments), :mod:`.main` (thin
layer: parse, call the library, print)."""

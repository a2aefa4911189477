"""The ``stand`` command line, a thin layer (parse, call the library, print):
:mod:`.main` (the entry point ``stand.cli.main:main``: guards, error lines, exit codes),
:mod:`.parser` (commands and their arguments), the commands by group -- :mod:`.simulation`
(run, accuracy, experiment, theory, sweep, stress, warmup), :mod:`.analysis` (analyze, report,
influence, balance, daq), :mod:`.images` (snapshot, video, track, strobe) -- :mod:`.common` (what
they share) and :mod:`.warmup` (every compiled kernel of stand, dsp and vision, ahead of use)."""

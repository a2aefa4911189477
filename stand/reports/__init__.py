"""Reports (issue 9): balancing quality (`stand report`), error against run
time (`stand accuracy -o`), numerical stability on stiff and extreme cases
(`stand stress`).  Each is a JSON document (the source of truth, schema in
docs/reports.md) rendered to one self-contained HTML file by :mod:`.html`.
:mod:`.video` writes a recording's screen frames as an mp4 beside the tracked and true
spot (`stand video`)."""

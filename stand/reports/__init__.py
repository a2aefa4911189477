"""Reports (issue 9): balancing quality (`stand report`), error against run
time (`stand accuracy -o`), numerical stability on stiff and extreme cases
(`stand stress`).  Each is a JSON document (the source of truth, schema in
docs/reports.md) rendered to one self-contained HTML file by :mod:`.html`."""

"""Test-session hooks: print the adversarial harness' table at the end of the run
(tests/test_adversarial.py records it as a user property; this works under pytest-xdist)."""

_TABLES = []


def pytest_runtest_logreport(report):
    if report.when == "call":
        for key, value in getattr(report, "user_properties", ()):
            if key == "adversarial_table":
                _TABLES.append(value)


def pytest_terminal_summary(terminalreporter):
    for table in _TABLES:
        terminalreporter.write_sep("-", "adversarial harness")
        terminalreporter.write_line(table)

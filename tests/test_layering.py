"""dsp and vision are leaves: they import neither stand nor each other."""
import ast
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
FORBIDDEN = {"dsp": {"stand", "vision"}, "vision": {"stand", "dsp"}}


@pytest.mark.parametrize("package", sorted(FORBIDDEN))
def test_leaf_packages_do_not_import_stand_or_each_other(package):
    bad = []
    for path in (ROOT / package).rglob("*.py"):
        tree = ast.parse(path.read_text(), filename=str(path))
        for node in ast.walk(tree):
            names = []
            if isinstance(node, ast.Import):
                names = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                names = [node.module]
            for n in names:
                if n.split(".")[0] in FORBIDDEN[package]:
                    bad.append(f"{path.relative_to(ROOT)}: imports {n}")
    assert not bad, bad
    assert (ROOT / package / "__init__.py").exists()

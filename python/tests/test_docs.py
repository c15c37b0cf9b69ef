"""docs/python.md's notebook runs as written on the bundled log (with a stand-in for matplotlib
when it is not installed: the plotting calls are then not drawn, the rest runs)."""

import os
import re
import sys
from unittest import mock

from conftest import SOURCE


def test_the_notebook_example_runs(monkeypatch, exe):
    with open(os.path.join(SOURCE, "docs", "python.md")) as f:
        blocks = re.findall(r"```python\n(.*?)```", f.read(), re.S)
    notebook = next(b for b in blocks if "dynamap.map(" in b)
    try:
        import matplotlib
        matplotlib.use("Agg")
    except ImportError:
        fake = mock.MagicMock()
        fake.pyplot.subplots.return_value = (mock.MagicMock(), [mock.MagicMock(), mock.MagicMock()])
        monkeypatch.setitem(sys.modules, "matplotlib", fake)
        monkeypatch.setitem(sys.modules, "matplotlib.pyplot", fake.pyplot)
    monkeypatch.chdir(SOURCE)
    scope = {}
    exec(compile(notebook, "docs/python.md", "exec"), scope)
    r = scope["r"]
    assert len(r.objects) == r.summary["objects"]["total"] and len(r.poses) > 0

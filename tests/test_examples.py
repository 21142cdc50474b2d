"""The example notebooks run, top to bottom, in a fresh kernel: they never rot.

Each notebook asserts its own results (the verdicts of the paper's claims, the
rank of the user's robot, a falling covariance trace), so an execution without
error is a check of those statements, not only of the code running.
"""

from pathlib import Path

import nbclient
import nbformat
import pytest

EXAMPLES = Path(__file__).resolve().parents[1] / "examples"


@pytest.mark.parametrize("name", ["own_robot", "paper_claims", "filters"])
def test_notebook_runs(name, tmp_path):
    book = nbformat.read(EXAMPLES / f"{name}.ipynb", as_version=4)
    client = nbclient.NotebookClient(book, timeout=300, kernel_name="python3", resources={"metadata": {"path": str(tmp_path)}})
    client.execute()
    outputs = [o for cell in book.cells if cell.cell_type == "code" for o in cell.outputs]
    assert not [o for o in outputs if o.output_type == "error"]
    assert outputs, "the notebook printed nothing"

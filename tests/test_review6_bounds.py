"""Two hangs found by the black-box review of 2026-12-08 (review6): a FIFO given
to ``verify-proof`` blocked on its read for ever, and ``check --point --orders K``
ignored ``--budget`` (K = 100,000 on three constant states ran for hours).

References: a FIFO is not a regular file (``stat.S_ISREG`` is false for it), so
it is refused as a model file already is (exit 2); the rank at a point with
orders 0..6000 costs about 10 s of CPU on the model below (the rows are
quadratic in K), so a budget of 1 s cannot hold it and the answer must be
"undecided", exit 3, with no rank stated at the point.
"""
from __future__ import annotations

import json
import os
import threading

from observability.cli import main

MODEL = """
name = "wset"
states = ["x", "y", "z"]
[dynamics]
x = "0"
y = "0"
z = "0"
[outputs]
h1 = "x"
h2 = "y"
h3 = "z*(x+y)"
"""


def test_verify_proof_refuses_a_fifo_without_reading_it(tmp_path, capsys):
    fifo = tmp_path / "proof.fifo"
    os.mkfifo(fifo)
    codes: list[int] = []
    worker = threading.Thread(target=lambda: codes.append(main(["verify-proof", str(fifo)])), daemon=True)
    worker.start()
    worker.join(60)  # a hang guard, not a speed budget: the refusal reads nothing
    if worker.is_alive():  # release the blocked open() so that the thread can end
        with open(fifo, "w"):
            pass
        worker.join(60)
        raise AssertionError("verify-proof blocked on a FIFO")
    assert codes == [2]
    assert "not a regular file" in capsys.readouterr().err


def test_point_orders_are_bounded_by_the_budget(tmp_path, capsys):
    model = tmp_path / "w.toml"
    model.write_text(MODEL)
    code = main(["check", str(model), "--point", "x=0,y=0,z=0", "--orders", "6000", "--budget", "1",
                 "--format", "json"])
    record = json.loads(capsys.readouterr().out)
    assert code == 3
    assert record["at_point"]["rank"] is None
    assert "did not fit --budget 1 s" in record["at_point"]["details"]
    assert record["rank"] == 3  # the generic verdict (x, y and z (x + y): det = x + y) is still printed

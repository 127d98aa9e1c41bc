"""ScanWorker with threaded=False (a deterministic replay): folds in the caller, in order."""

from __future__ import annotations

from zenros.services.slam.worker import ScanWorker


def test_an_inline_worker_folds_at_once_and_survives_a_bad_item() -> None:
    folded: list[int] = []
    errors: list[BaseException] = []

    def fold(i: int) -> None:
        if i == 2:
            raise ValueError("bad scan")
        folded.append(i)

    w: ScanWorker[int] = ScanWorker(fold, capacity=1, on_error=errors.append, threaded=False)
    w.start()
    for i in range(5):
        w.submit(i)
        assert i == 2 or folded[-1] == i  # done before submit returns
    assert folded == [0, 1, 3, 4] and w.skipped == 0 and w.done == 5
    assert [str(e) for e in errors] == ["bad scan"]
    assert w.idle() and w.wait_idle(0.0)
    w.close()

"""`cancel_and_wait`: a cancel that overtook its goal (the server did not know it yet) is asked
again once the goal is accepted; a cancel the server refused knowing the goal is not."""

from __future__ import annotations

import threading

from zenros.services.tasks.link import cancel_and_wait


class FakeHandle:
    """A goal handle whose server accepts the goal after ``accept_after`` cancels were sent;
    a cancel sent before that is refused (unknown goal id), as the real server answers."""

    def __init__(self, accept_after: int, refuse_known: bool = False) -> None:
        self.accepted: bool | None = None
        self.accept_after = accept_after
        self.refuse_known = refuse_known
        self.cancels = 0
        self.ended = threading.Event()

    @property
    def done(self) -> bool:
        return self.ended.is_set()

    def cancel(self, timeout: float = 5.0) -> bool:
        self.cancels += 1
        if self.accepted is None:
            if self.cancels >= self.accept_after:
                self.accepted = True  # the goal's acceptance arrives just after the refusal
            return False
        if self.refuse_known:
            return False
        self.ended.set()  # canceling, then CANCELED
        return True

    def wait_accepted(self, timeout: float | None = None) -> bool:
        return bool(self.accepted)

    def result(self, timeout: float | None = None) -> None:
        self.ended.wait(timeout)


def test_a_cancel_that_overtook_its_goal_is_sent_again_once_accepted() -> None:
    h = FakeHandle(accept_after=1)
    cancel_and_wait(h, 1.0)
    assert h.cancels == 2 and h.done


def test_a_cancel_refused_for_a_known_goal_is_not_repeated() -> None:
    h = FakeHandle(accept_after=1, refuse_known=True)
    h.accepted = True
    cancel_and_wait(h, 0.2)
    assert h.cancels == 1 and not h.done

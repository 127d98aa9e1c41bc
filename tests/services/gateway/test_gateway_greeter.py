"""`Greeter`: once per approach, not again while the person stays, again after they left."""

from __future__ import annotations

import pytest
from zenros.services.gateway.state.greeter import Greeter


def test_a_person_coming_near_is_greeted_once_per_approach() -> None:
    g = Greeter(near=1.5, far=2.0, forget=2.0)
    assert not g.update([(3.0, 0.0)], 0.0)  # far off
    assert g.update([(1.4, 0.2)], 1.0)  # came near: greet
    assert not any(g.update([(1.0, 0.0)], t) for t in (1.5, 2.0, 5.0))  # standing by
    assert not g.update([], 5.5)  # the detector missed them a moment
    assert not g.update([(1.2, 0.0)], 6.0)  # still the same approach
    assert not g.update([(2.5, 0.0)], 7.0)  # walking off...
    assert not g.update([], 8.5)  # ...gone (nobody within 2 m since 6.0)
    assert g.update([(0.0, 1.3)], 9.0)  # back: greeted again


def test_the_nearest_person_counts_and_bad_distances_are_refused() -> None:
    g = Greeter()
    assert g.update([(4.0, 0.0), (1.0, 1.0)], 0.0)
    with pytest.raises(ValueError, match="near <= far"):
        Greeter(near=2.0, far=1.0)

"""Cost values: the static layer's occupancy → cost and the published cost → occupancy."""

from __future__ import annotations

import numpy as np
from zenros.services.nav.costmap import (
    INSCRIBED_INFLATED_OBSTACLE,
    LETHAL_OBSTACLE,
    NO_INFORMATION,
    cost_to_occupancy,
    occupancy_to_cost,
)


def test_published_scale_is_costmap_2d_translation_table() -> None:
    costs = np.arange(256, dtype=np.uint8)
    occ = cost_to_occupancy(costs)
    assert occ.dtype == np.int8
    assert occ[0] == 0
    assert occ[INSCRIBED_INFLATED_OBSTACLE] == 99
    assert occ[LETHAL_OBSTACLE] == 100
    assert occ[NO_INFORMATION] == -1
    for c in range(1, 253):
        assert occ[c] == 1 + (97 * (c - 1)) // 251
    assert occ[1] == 1 and occ[252] == 98
    assert np.all(np.diff(occ[1:253].astype(int)) >= 0)


def test_static_layer_trinary() -> None:
    occ = np.array([[-1, 0, 50, 99, 100]], dtype=np.int8)
    assert occupancy_to_cost(occ).tolist() == [[0, 0, 0, 0, 254]]
    assert occupancy_to_cost(occ, track_unknown_space=True).tolist() == [[255, 0, 0, 0, 254]]
    assert occupancy_to_cost(occ, lethal_cost_threshold=50).tolist() == [[0, 0, 254, 254, 254]]


def test_static_layer_scaled() -> None:
    occ = np.array([[0, 25, 50, 99, 100, -1]], dtype=np.int8)
    got = occupancy_to_cost(occ, trinary_costmap=False, track_unknown_space=True)
    # Nav2: v / lethal_threshold * 254, truncated
    scaled = [int(v / 100 * 254) for v in (25, 50, 99)]
    assert got.tolist() == [[0, *scaled, 254, 255]]


def test_static_layer_reads_bytes_unsigned() -> None:
    # Nav2 reads the int8 cell as an unsigned char: -2 is 254, above the lethal threshold
    occ = np.array([[-2, -100]], dtype=np.int8)
    assert occupancy_to_cost(occ).tolist() == [[254, 254]]

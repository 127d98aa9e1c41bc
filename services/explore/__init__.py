"""Frontier exploration (explore_lite's rules): the ``explore`` node maps a site with no one
driving, nearest reachable frontier first, through nav's ``navigate_to_pose``
(docs/mapping.md, "Exploration"). ``frontiers`` and ``explorer`` are plain Python; ``node``
wires them to Zenoh."""

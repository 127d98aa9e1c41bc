"""The navigation service: map server, localisation, planner and controller, Nav2-style actions.

Packages, bottom to top (each imports only those below it; tests/services/nav/test_layout.py):
``maps`` and ``localization``; ``costmap``; ``planning``; ``motion``; then ``core`` (`NavCore`,
the parts put together) and ``params``; ``actions`` (the Zenoh-facing action servers); ``node``.
"""

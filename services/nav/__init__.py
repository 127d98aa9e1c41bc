"""The navigation service: map server, localisation, planner and controller, Nav2-style actions."""

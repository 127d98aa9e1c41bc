"""Localisation: the robot's pose in ``map`` (odometry corrected by scan matching). Imports nothing
else of nav."""

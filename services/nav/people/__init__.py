"""People around the robot: the leg detector on the laser and the person follower."""

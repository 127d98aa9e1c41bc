"""The tasks service: the robot API's tasks and actions, run as state machines, persisted."""

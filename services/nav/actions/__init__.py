"""Actions: nav's Nav2-style action servers (navigation, behavior server, routines), the coverage
service, the ``nav/status`` message and the ROS message conversions they share. Built on `core`."""

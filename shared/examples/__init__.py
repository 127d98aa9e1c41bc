"""Small example nodes (talker, listener, add_two_ints server), as in the ROS tutorials."""

"""What the gateway knows: the robot's state and GalileoStatus (`core`, `status`), which
backends are up (`presence`), settings, tokens, the server configuration and speech."""

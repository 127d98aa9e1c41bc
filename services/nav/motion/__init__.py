"""Motion: behaviors (tick-driven robot motion: navigate, dock, patrol, local moves,
recoveries), the controller that follows a path, and the control loop that ticks the active
behavior. Imports planning (a behavior asks for plans); no Zenoh."""

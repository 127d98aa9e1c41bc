"""The simulated chassis: a diff-drive base with laser, battery and dock in a 2-D world."""

"""The §1.3 UDP door: the discovery broadcast."""

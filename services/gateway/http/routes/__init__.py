"""The REST operations, one module per group of the robot API (specs: docs/gateway.md)."""

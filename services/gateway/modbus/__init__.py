"""The docs/robot-api.md §14 Modbus TCP door: the server (`front`) and its register tables
(`tables`)."""

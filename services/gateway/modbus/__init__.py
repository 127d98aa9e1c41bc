"""The §14 Modbus TCP door: the server (`front`) and its register tables (`tables`)."""

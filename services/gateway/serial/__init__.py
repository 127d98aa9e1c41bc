"""The docs/robot-api.md §13 serial door: the bridge on a serial port (`bridge`) and its frames
(`frame`)."""

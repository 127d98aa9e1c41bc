"""The protocol gateway: the robot API over REST, WebSocket, Modbus TCP, serial and UDP."""

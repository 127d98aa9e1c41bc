"""The protocol gateway: the robot API over REST, WebSocket, Modbus TCP, serial and UDP.

Sub-packages, imports pointing one way (docs/architecture.md):

- `state`: what the gateway knows (robot status, presence of backends, settings, tokens);
- `ports`: its zenros-side clients to the robot (nav, tasks, chassis IO, topics); they raise
  `errors.PortError`s, never HTTP errors;
- doors, each a protocol front end over the ports and the state: `http` (REST, the topic
  WebSocket, the dashboard), `modbus`, `serial`, `udp` (discovery), `rosbridge`, `foxglove`,
  and `ros2` (the DDS bridge, its own process);
- `node` wires them together; `static` holds the dashboard's files.

No port imports a door, and no module imports another service.
"""

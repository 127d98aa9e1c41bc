"""The gateway's ports to the robot: zenros-side clients of nav, tasks and the chassis, the
topic hub, the robot's files. They use `state` and raise `..errors.PortError`s; they never
import a door (http, modbus, serial, udp, rosbridge, foxglove)."""

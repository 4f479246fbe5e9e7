"""Galileo's native command bytes and status frame (galileo-wire-protocols §1-§2), and the
wires that carry them: the serial line, ``/galileo/cmds`` on the WebSocket and on rosbridge.
Modbus and the UDP fast protocol drive the robot through the same :mod:`.control`."""

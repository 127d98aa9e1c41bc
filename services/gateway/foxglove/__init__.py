"""Foxglove: the live zenros graph served to Foxglove through foxglove-sdk (optional extra
``zenros[foxglove]``), with JSON-schema channels named after the ROS types so its 3D panel
shows map, scan, TF and plan; see docs/foxglove.md.

`bridge` (``FoxgloveBridge``) needs foxglove-sdk; `schema` does not.
"""

"""The tf service: a buffer server for thin clients, static transforms from configuration,
and per-frame statistics (tf_monitor)."""

"""The schedule server (docs/fleet.md, "Schedule server"): the fleet's shared store of map
archives, which robots put their maps on and get them from (docs/robot-api.md §6.3
``upload_map``, ``download_map``)."""

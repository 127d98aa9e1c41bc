"""Maps: the maps folder, the map in use and its services, and each map's nav data
(nav points, paths, keep-out shapes, charge pose, point connections). Imports nothing else of nav."""

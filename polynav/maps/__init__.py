"""Maps and costmaps: occupancy grids, their file formats, and the layered costmap."""

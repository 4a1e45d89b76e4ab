//! Static geometry, occupancy grid, distance field and ray casting.

"""The mapping service: occupancy-grid SLAM from ``scan`` and ``odom`` (docs/mapping.md)."""

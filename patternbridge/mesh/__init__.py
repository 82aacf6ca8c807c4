"""Character meshes: loading with unit/up-axis detection, skeleton, skinning, landmarks."""

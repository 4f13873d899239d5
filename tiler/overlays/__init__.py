"""Multi-scale annotation overlays: patch and level images composited per level of detail and
tiled into a dataset, with their texts."""

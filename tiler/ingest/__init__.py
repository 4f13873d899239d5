"""``lanterna import``: sources (files, folders, description files, the seed paper's scenes,
spectral bands) planned as the layers of one dataset."""

"""File formats of relightable models: PTM and HSH readers and their models, Relight's web format,
plane layouts (three channels per IIIF image) and file-backed planes. Knows nothing of datasets."""

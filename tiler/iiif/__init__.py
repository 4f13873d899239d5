"""IIIF Image API 3: pure pyramid geometry, level-0 pyramids (pyvips ``dzsave`` with its gaps
fixed), pyramidal TIFFs, and the spec's identifiers."""

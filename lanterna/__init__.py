"""Lanterna: annotated, multi-layered relightable images on the web, as IIIF."""

__version__ = "0.1.0"

"""Preset libraries: named rendering configurations of a dataset's layers (docs/presets.md)."""

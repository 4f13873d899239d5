"""The data flow from source files to IIIF datasets, one subpackage per stage.

See docs/architecture.md for the stages and what each may import.
"""

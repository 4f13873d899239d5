"""lanterna.tiler"""

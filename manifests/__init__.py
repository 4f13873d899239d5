"""lanterna.manifests"""

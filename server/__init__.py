"""lanterna.server"""

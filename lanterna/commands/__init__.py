"""One module per ``lanterna`` command; each has ``register(sub)`` adding its sub-parser."""

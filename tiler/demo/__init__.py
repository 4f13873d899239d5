"""The demo object: a synthetic relief tablet under a virtual dome, fitted and written as a
dataset with one layer of every kind."""

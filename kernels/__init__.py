"""Warp kernels of rswarp, installed as ``rswarp.kernels``; they take plain arrays, never rswarp objects."""

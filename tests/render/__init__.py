"""Tests of morph.render, one file per module; test_render.py: the package's own API."""

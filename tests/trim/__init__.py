"""Tests of morph.trim, one file per module; test_trim.py: the package's own API."""

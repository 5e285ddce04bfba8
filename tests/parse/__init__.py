"""Tests of morph.parse, one file per module."""

"""Tests of morph.fonts, one file per module."""

"""Tests of morph.cli: the command group and its error contract, and the shared options."""

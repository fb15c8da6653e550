"""Tests of exdex.cli: one file per command module (a package, so that its
file names may repeat those of the library's own tests)."""

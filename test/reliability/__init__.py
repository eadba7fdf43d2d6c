"""Reliability tests: bad input, faults and load (a package, so its conftest is its own)."""

"""Mutants of the build exercises' worked solutions, and the list of those that cannot be told apart."""

"""Assemblies: two or more rigid bodies in contact, a statue on its plinth, a column of drums (:mod:`.stack`)."""

"""Screening after an earthquake: the event's ShakeMap, and each asset's probability of overturning in it."""

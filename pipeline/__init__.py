"""rockscreen: screen strong-motion records for the overturning of free-standing rigid blocks."""

__version__ = "0.1.0"

"""max2code: Maxima-first generator of exact time-of-collision code."""
__version__ = "0.1.0"

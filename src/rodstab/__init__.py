"""rodstab: elastic stability of Kirchhoff rods and rings in circular or straight states.

Reference: S. Leanza, R. R. Zhao, J. W. Hutchinson, "On the elastic stability of folded
rings in circular and straight states" (the paper; equation numbers cited throughout).
"""

__version__ = "0.1.0"

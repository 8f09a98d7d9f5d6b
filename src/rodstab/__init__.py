"""rodstab: elastic stability of Kirchhoff rods and rings in circular or straight states.

Reference: S. Leanza, R. R. Zhao, J. W. Hutchinson, "On the elastic stability of folded
rings in circular and straight states" (the paper; equation numbers cited throughout).
"""

__version__ = "0.1.0"


def __getattr__(name: str) -> object:
    """Import ``rodstab.sweep`` on first use (PEP 562), so that ``import rodstab`` stays light.

    ``rodstab.sweep(design, vary={...})`` is :func:`rodstab.sweep.run` (the module is
    callable); ``rodstab.sweep.sweep`` the sweep returning rows.
    """
    if name == "sweep":
        import importlib

        return importlib.import_module(f"{__name__}.sweep")
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")

"""Geometrically exact discrete rods: energy, exact gradient and Hessian, equilibria, stability.

:mod:`.jets` (second-order forward differentiation, exact) -> :mod:`.discrete` (the discrete
Cosserat rod built from a :class:`rodstab.model.Assembly`) -> :mod:`.solve` (Newton with line
search, constrained Hessian spectrum).
"""

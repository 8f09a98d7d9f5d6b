"""Finite-element second variation P2 (eq 2.12) for planar rod assemblies (the general engine).

Pipeline: :mod:`rodstab.model` (segments, welds, supports, validation; shared with the
other solvers) -> :mod:`.elements` (element
matrices) -> :mod:`.assembly` (global matrices, constraints, rigid modes) -> :mod:`.solve`
(load-factor interval through :func:`rodstab.numerics.pencil_interval`).
"""

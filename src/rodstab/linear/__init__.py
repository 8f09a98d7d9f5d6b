"""Finite-element second variation P2 (eq 2.12) for planar rod assemblies (the general engine).

Pipeline: :mod:`.model` (segments, welds, supports, validation) -> :mod:`.elements` (element
matrices) -> :mod:`.assembly` (global matrices, constraints, rigid modes) -> :mod:`.solve`
(load-factor interval through :func:`rodstab.numerics.pencil_interval`).
"""

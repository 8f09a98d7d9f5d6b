"""Closed forms and characteristic equations of the paper, one module per problem.

Local symbols follow the paper letter for letter (``b1``, ``b2``, ``M``, ``q``). The paper uses
lambda for two things: the wavenumber ratio of Section 3.2 (here ``lam``/``lam2``) and the load
factor ``B3 kappa L / sqrt(B1 B2)`` of Sections 4-5 (here also ``lam``, in the modules of
Sections 4-5, never ``load_factor``: that is the engine's ``mu``); see docs/notation.md.
"""

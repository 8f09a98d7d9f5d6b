"""Multistability: the states of a ring, their stability atlas, and the ways between them.

* :mod:`.states` -- closed planar held states of uniform moment of a ring of welded rods;
* :mod:`.atlas` -- the stable interval of each state against a design parameter;
* :mod:`.discover` -- equilibria nobody named, by deflated Newton on one discrete rod;
* :mod:`.transitions` -- a stable state loaded until it snaps, and where it goes;
* :mod:`.barrier` -- energy barriers between two stable states (saddle by continuation);
* :mod:`.string_method` -- minimum energy paths and their saddles by the string method.

Built on the engines (:mod:`rodstab.linear`, :mod:`rodstab.nonlinear`, :mod:`rodstab.transfer`)
and below :mod:`rodstab.problems` and the CLI, which it never imports. Nothing is re-exported
here: each module is imported where it is used.
"""

"""Pictures: data in, figure out, no mathematics (matplotlib's object API, never pyplot).

* :mod:`.plots` -- assemblies and their critical modes, equilibria (3D boxes, animations,
  interactive HTML), ring states, stable bands, sections, barrier paths;
* :mod:`.ribbons` -- the geometry of rods drawn as boxes of their section's proportions;
* :mod:`.transition_graph` -- the figure of a transition graph;
* :mod:`.animations` -- a continuation's branch (GIF, HTML) and a barrier's path (GIF), drawn
  from the solvers' results with :mod:`.plots`.

The figures of the reproduction report are in :mod:`rodstab.report.figures`, which draws with
these. Nothing is re-exported here: matplotlib is imported only by a command that draws.
"""

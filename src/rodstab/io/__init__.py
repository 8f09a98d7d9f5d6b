"""Reading and writing: design files, polygon files, ``--vary`` grammar, run outputs.

* :mod:`.design` -- TOML design files -> :class:`rodstab.model.Assembly` (the format, strict
  validation); :mod:`.schema` every table and key of the format, declared once (the reader's
  keys and bounds, and the generated format reference); :mod:`.fields` its typed readers,
  :mod:`.section_table` its section tables;
* :mod:`.outline` -- polygon outlines of a section from JSON, CSV or DXF files;
* :mod:`.vary` -- the ``--vary KEY=START:STOP[:N]`` grammar and :func:`.vary.set_design_value`;
* :mod:`.outputs` -- output paths checked before a run, atomic writes, run locks.

Nothing is re-exported here, so that importing :mod:`.outputs` (the CLI does at start-up)
does not import the design reader.
"""

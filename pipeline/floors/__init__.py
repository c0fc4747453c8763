"""Floor motion of buildings: the continuous shear-flexural model (Miranda & Taghavi 2005).

A library like :mod:`pipeline.rocking`: it never imports the configuration, the CLI, the run layer, the
store or the report. :mod:`.model` gives the modes, :mod:`.motion` the floor acceleration history.
"""

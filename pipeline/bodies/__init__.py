"""The body models: one registry (:mod:`.registry`) of every model that judges a block, each in a module of its own
(:mod:`.planar`, :mod:`.solids`, :mod:`.scanned`) following one contract (:mod:`.contract`), and the warm-up of
their compiled kernels (:mod:`.warmup`)."""

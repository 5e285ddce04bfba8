"""Reproduction of the paper beside the engine: the comparison methods of its Sec. 4
and the sampled measures of Sec. 5.2 (:mod:`.methods`), used by ``--method`` and the
benchmark, never by a default sum."""

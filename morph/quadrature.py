"""Gauss-Legendre rules on [-1, 1] without importing numpy.polynomial.

The areas and moments (:mod:`morph.moments`, 24 points) and the curve fitter
(:mod:`morph.export.fit`, 8 and 16 points) integrate with fixed rules.  Importing
``numpy.polynomial`` for :func:`numpy.polynomial.legendre.leggauss` loads all six of
its polynomial classes (~5 ms of CPU in every process that sums a shape), and the
first call solves an eigenproblem; the rules those modules use are tabulated here:
the non-negative nodes and their weights, to the last bit of ``leggauss`` (which
makes them symmetric, as here), so the results do not change.  Other sizes fall back
to ``leggauss``.  ``tests/test_quadrature.py`` checks the tables against it and
against the exact integrals of the monomials the rules must integrate exactly.
"""

import functools

import numpy as np

__all__ = ["gauss_legendre"]

#: n -> (nodes in (0, 1), ascending; their weights)
_HALVES = {
    8: ((0.18343464249564978, 0.525532409916329, 0.7966664774136267, 0.9602898564975362),
        (0.36268378337836166, 0.3137066458778869, 0.22238103445337443, 0.10122853629037706)),
    16: ((0.09501250983763744, 0.2816035507792589, 0.45801677765722737, 0.6178762444026438,
          0.755404408355003, 0.8656312023878318, 0.9445750230732326, 0.9894009349916499),
         (0.18945061045506864, 0.18260341504492364, 0.16915651939500265, 0.1495959888165767,
          0.12462897125553407, 0.0951585116824926, 0.062253523938647456,
          0.027152459411754176)),
    24: ((0.06405689286260563, 0.1911188674736163, 0.3150426796961634, 0.4337935076260451,
          0.5454214713888396, 0.6480936519369755, 0.7401241915785544, 0.820001985973903,
          0.8864155270044011, 0.9382745520027328, 0.9747285559713095, 0.9951872199970213),
         (0.12793819534675202, 0.12583745634682825, 0.1216704729278033, 0.11550566805372552,
          0.10744427011596556, 0.09761865210411393, 0.0861901615319532, 0.07334648141108016,
          0.05929858491543636, 0.04427743881741941, 0.02853138862893356,
          0.01234122979998869)),
}

#: the sizes answered from the tables (others call numpy's leggauss)
TABULATED = tuple(sorted(_HALVES))


@functools.lru_cache(maxsize=None)
def gauss_legendre(n):
    """``(nodes, weights)`` of the n-point Gauss-Legendre rule on [-1, 1], nodes
    ascending (as :func:`numpy.polynomial.legendre.leggauss`); the arrays are
    shared between callers and read-only."""
    if n in _HALVES:
        pos, w = (np.array(v) for v in _HALVES[n])
        nodes, weights = np.concatenate([-pos[::-1], pos]), np.concatenate([w[::-1], w])
    else:
        from numpy.polynomial.legendre import leggauss

        nodes, weights = leggauss(n)
    nodes.flags.writeable = weights.flags.writeable = False
    return nodes, weights

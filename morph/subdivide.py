"""Algorithm 5.1: the one subdivision driver of every convolution method, and the
record of a convolution piece.

A compatible pair (:mod:`morph.gauss`) is approximated by one piece, bounded, and
split until every bound is within the tolerance, level by level on batches of
sub-pairs (:func:`subdivide_nodes`).  :data:`QAC_METHOD` is certified QAC (Algorithm
4.1 of :mod:`morph.qac`: role choice, a-priori bound, split where the bound peaks),
what every sum runs (:mod:`morph.convolve`); the paper's seven other methods and its
sampled error measures are in :mod:`morph.paper.methods`, outside a sum's imports.
"""

from collections import namedtuple

import numpy as np

from . import piece as pc
from . import qac
from .errors import DegenerateCurveError, ToleranceNotMetError

__all__ = ["METHODS", "ConvPiece", "Method", "QAC_METHOD", "subdivide", "subdivide_nodes",
           "turning_sign"]

#: The convolution methods of a sum (Sec. 4): certified QAC here, the paper's seven
#: others in :mod:`morph.paper.methods`.
METHODS = ("ctc", "lsc", "bic", "hic", "qac", "lrc", "tmc", "src")


def turning_sign(piece):
    """+1 if the tangent of a monotone piece turns counter-clockwise, -1 if clockwise.

    Raises DegenerateCurveError for a straight piece (no turning to match against).
    """
    t0, t1 = pc.end_tangents(piece)
    c = float(pc.cross2(t0, t1))
    if c == 0.0:
        if float(np.dot(t0, t1)) > 0:
            raise DegenerateCurveError("straight piece: tangent does not turn", piece)
        raise DegenerateCurveError("piece turns by pi: not a compatible piece", piece)
    return 1 if c > 0 else -1



# ====================================================================== driver
# Algorithm 5.1, level by level.  A *node* is one compatible sub-pair; a batch of
# nodes is a dict of arrays with one row per node (stacks of pieces of one degree,
# parameter intervals, ...), so that a method may work on all nodes of a level at
# once (QAC does: :mod:`morph.qac`) or loop over them (the other seven methods).

def _take(nodes, rows):
    """The rows of a node batch (every column)."""
    return {k: v[rows] for k, v in nodes.items()}


def _concat(batches):
    """Node batches with the same columns, one after the other."""
    return {k: np.concatenate([b[k] for b in batches]) for k in batches[0]}


def _objects(items):
    """A 1-D object array of the items (arrays of one shape stay separate)."""
    out = np.empty(len(items), object)
    for k, item in enumerate(items):
        out[k] = item
    return out


def subdivide_nodes(nodes, one_piece, bound, split, tol, max_depth=24, stacked=False):
    """Algorithm 5.1: approximate, bound, split until every bound <= tol.

    The one subdivision driver of every method (and of :mod:`morph.convolve`).
    ``nodes``: a dict of arrays, one row per root sub-pair, with at least the
    columns ``ca`` and ``cb`` (the sub-pieces, kept on the error); the driver adds
    ``depth``, the halvings left (``max_depth`` at the roots).  Each level:

    - ``bound(nodes, tol) -> (error (k,), where (k,))``: the error of each node's
      approximation (an a-priori bound or a measure: the method's contract says
      which) and where to split it; it may add columns to ``nodes`` for the other
      two callables (the role QAC chose, the piece a measure was taken on);
      a column ``tol`` in the root nodes gives each root its own tolerance
      (children inherit it, and ``bound`` gets that column instead of ``tol``);
    - ``one_piece(nodes) -> list``: the pieces of the nodes whose error is <= tol
      (None where the method rejects its piece: that node is split instead); with
      ``stacked``, ``one_piece(nodes) -> (ok, groups)`` the same on arrays: ``ok``
      (k,) the nodes with a piece, ``groups`` [(rows, stack)] their pieces
      (:func:`morph.qac.piece_stacks`);
    - ``split(nodes, where) -> (left, right)``: the columns of the two children
      of each node; columns it does not return are copied from the parent.

    Returns (done, pieces, errors): the accepted nodes (a dict of arrays, level by
    level), their pieces (a list; with ``stacked`` a :class:`morph.piece.Pieces` of
    the stacks of all levels, :func:`_joined`) and errors; the caller orders them.
    Raises ValueError for tol <= 0, ToleranceNotMetError (:func:`_not_met`) if a node
    fails after ``max_depth`` halvings.
    """
    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    nodes = dict(nodes, depth=np.full(len(next(iter(nodes.values()))), max_depth))
    done, pieces, errors, count = [], [], [], 0
    while len(nodes["depth"]):
        limit = nodes["tol"] if "tol" in nodes else tol
        err, where = bound(nodes, limit)
        acc = np.nonzero(err <= limit)[0]
        accepted, has, got = _accepted(one_piece, _take(nodes, acc), stacked, count)
        ok = np.zeros(len(err), bool)
        ok[acc[has]] = True
        done.append(accepted if has.all() else _take(accepted, has))   # the rows ok
        pieces += got
        count += len(got) if not stacked else int(has.sum())
        errors.append(err[ok])
        fail = np.nonzero(~ok)[0]
        if not len(fail):
            break
        last = fail[nodes["depth"][fail] <= 0]
        if len(last):
            raise _not_met(nodes, err, limit, last, max_depth)
        parent = _take(nodes, fail)
        left, right = split(parent, where[fail])
        nodes = _concat([{**parent, **left}, {**parent, **right}])
        nodes["depth"] = nodes["depth"] - 1
    if stacked:
        pieces = _joined(pieces, count)
    return _concat(done), pieces, np.concatenate(errors)


def _not_met(nodes, err, limit, last, max_depth):
    """The ToleranceNotMetError of the nodes ``last`` of a level (errors ``err``
    above ``limit``) out of halvings: ``piece`` the first one's sub-pair (ca, cb),
    ``achieved`` its error, ``rows`` the ``pos`` column of them all (None where the
    nodes have none)."""
    r = last[0]
    return ToleranceNotMetError(
        "error %g above tolerance %g after %d splits"
        % (err[r], np.broadcast_to(limit, err.shape)[r], max_depth),
        piece=(nodes["ca"][r], nodes["cb"][r]), achieved=float(err[r]),
        rows=nodes["pos"][last] if "pos" in nodes else None)


def _accepted(one_piece, nodes, stacked, count):
    """(nodes, has, pieces) of the nodes of a level whose error is within tol:
    ``has`` the nodes ``one_piece`` gave a piece; ``pieces`` a list of them, or with
    ``stacked`` [(indices, stack)] with each piece's index among all accepted nodes
    so far (``count`` before this level)."""
    if not len(nodes["depth"]):
        return nodes, np.zeros(0, bool), []
    if not stacked:
        got = one_piece(nodes)
        has = np.array([p is not None for p in got], bool)
        return nodes, has, [p for p in got if p is not None]
    has, groups = one_piece(nodes)
    rank = np.cumsum(has) - 1 + count
    return nodes, has, [(rank[rows], stack) for rows, stack in groups]


def _joined(groups, n):
    """The :class:`morph.piece.Pieces` of ``n`` pieces given as [(indices, stack)]:
    the stacks with the same number of control points concatenated, their indices
    ascending."""
    by = {}
    for ks, stack in groups:
        by.setdefault(stack.shape[1], []).append((ks, stack))
    out = []
    for parts in by.values():
        ks = np.concatenate([k for k, _ in parts])
        order = np.argsort(ks, kind="stable")
        out.append((ks[order], np.concatenate([h for _, h in parts])[order]))
    return pc.Pieces(out, n)


class ConvPiece:
    """One piece of a convolution curve: the one record of every method, of
    Algorithm 5.1 (:func:`subdivide`) and of :func:`morph.convolve.convolution`.

    piece: (m+1, 3) homogeneous control points.  bound: its distance to the exact
    convolution curve: the a-priori bound for QAC (Eqs. 39-40) and for exact
    pieces (0), the measured error for the other methods.  kind: "qac",
    "translate", "chord" or a method's name.  type: 1, 2 or 3 (Fig. 20; 0 where not
    typed).  source: (loop in A, edge, loop in B, edge).  row: the pair's row in
    the table of compatible pairs (:class:`morph.convolve.GaussPair`, -1 when
    unknown).  c1, c2: the compatible sub-pair approximated, in the roles the
    method used (from :func:`subdivide`; None from ``convolution``): the piece
    approximates c1(t) + c2(s(t)) and is parametrised like c1, which is the part of
    the original C1 except where certified QAC chose the other role (Sec. 4.4)
    (reversed where the two turn opposite ways, so that it runs like the piece).
    t: the sub-pair's parameter interval on the original C1.

    A plain class: processing a dataclass costs every process about half a ms.
    """

    def __init__(self, piece, bound=0.0, kind="qac", type=0, source=(), row=-1, c1=None,
                 c2=None, t=(0.0, 1.0)):
        self.piece, self.bound, self.kind, self.type = piece, bound, kind, type
        self.source, self.row, self.c1, self.c2, self.t = source, row, c1, c2, t

    def __repr__(self):
        return "ConvPiece(kind=%r, type=%r, bound=%r, source=%r, row=%r, t=%r)" % (
            self.kind, self.type, self.bound, self.source, self.row, self.t)


class Method(namedtuple("Method", "root one_piece bound split role_pair")):
    """A method for :func:`subdivide`: ``root(c1, c2)`` the root node batch of a pair,
    ``one_piece``, ``bound``, ``split`` the callables of :func:`subdivide_nodes`, and
    ``role_pair(nodes, r)`` the (c1, c2) of an accepted node as in :class:`ConvPiece`."""


def _qac_root(c1, c2):
    """The root node of a pair for :mod:`morph.qac`'s callables."""
    c1, c2 = np.asarray(c1, float), np.asarray(c2, float)
    sa, sb = turning_sign(c1), turning_sign(c2)
    a0, a1 = pc.end_tangents(c1)
    th0 = float(np.arctan2(a0[1], a0[0]))
    th1 = th0 + float(np.arctan2(pc.cross2(a0, a1), np.dot(a0, a1)))
    return {"ca": c1[None], "cb": c2[None], "ha": pc.tangent_numerator(c1)[None],
            "hb": pc.tangent_numerator(c2)[None], "sa": np.array([sa]),
            "sb": np.array([sb]), "lo": np.array([min(th0, th1)]),
            "hi": np.array([max(th0, th1)]), "t0": np.zeros(1), "t1": np.ones(1)}


#: Certified QAC, Algorithm 4.1 exactly as :mod:`morph.convolve` runs it: role
#: choice, a-priori bound, split where the bound peaks (:mod:`morph.qac`).
QAC_METHOD = Method(_qac_root, qac.piece_nodes, qac.bound_nodes, qac.split_nodes,
                    qac.role_pair)


def subdivide(c1, c2, method, tol, max_depth=24, kind=""):
    """Algorithm 5.1 on one compatible pair: a list of :class:`ConvPiece` in C1's order.

    ``method`` is a :class:`Method` (:func:`method_functions`, :func:`pair_method`);
    :func:`subdivide_nodes` does the work.  The pieces' kind is ``kind`` (the
    method's name), or QAC's own kinds (qac, translate, chord) where its nodes say.
    Raises ValueError for tol <= 0, ToleranceNotMetError after ``max_depth`` halvings.
    """
    done, pieces, errors = subdivide_nodes(method.root(c1, c2), method.one_piece,
                                           method.bound, method.split, tol, max_depth)
    out = []
    for r in np.argsort(done["t0"], kind="stable"):
        a, b = method.role_pair(done, r)
        name = qac.KIND_NAMES[done["kind"][r]] if "kind" in done else kind
        out.append(ConvPiece(pieces[r], float(errors[r]), kind=name, c1=a, c2=b,
                             t=(float(done["t0"][r]), float(done["t1"][r]))))
    return out

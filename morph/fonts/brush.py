"""Brush-swept fonts (paper Fig. 5): every chosen glyph replaced by glyph ⊕ nib.

The nib is a convex region swept without rotation (a calligraphic pen held at a
fixed angle); the default is an exact ellipse (:func:`morph.piece.ellipse`).  Each
sum is computed with :func:`morph.minkowski.minkowski_sum` within the geometry share
of ``tol`` and its loops of rational pieces are converted to the font's curve type
within the export share (:func:`morph.budget.plan`, as every writer splits it;
plus what the sum's ``bound`` leaves of the geometry share, :func:`_export_tolerance`)
by :func:`morph.fonts.tables.contours_from_loops`
(TrueType: quadratics,
:func:`morph.export.loop_to_quadratics`; CFF: cubics,
:func:`morph.export.loop_to_beziers`; curves may span smooth joins), both with
certified bounds, so each written
outline is within ``tol`` font units of the exact glyph ⊕ nib before the points are
rounded to the integer grid (at most 0.71 unit more; see
:func:`morph.fonts.tables.clean_contour` for the clean-up of rounded contours).

**Fallback.**  A glyph whose sum raises (a :class:`morph.errors.MorphError` such as
``TopologyError``; any other exception is a programming error and stops the
command, :func:`morph.fonts.jobs.fallback_ladder`) does not stop the font.  It is computed
again by the same exact method at a quarter of the geometry share (other crossings
and flattenings; curves within tol as usual; kind "retry"), then with the nib turned
about its pen point by the angle that moves it by half the geometry share at most
(both ways; the sum at the other half, so the outline stays within ``tol``; kind
"rotated", :data:`morph.budget.TURN_SHARE`: this breaks exact
tangencies between the nib and straight glyph edges); if those raise too, by
:func:`morph.fonts.jobs.polygon_sum` (the glyph and the nib flattened within
``tol / 2`` each (:data:`morph.budget.POLYGON_SHARE`) and summed exactly by Clipper: within ``tol`` of the exact sum, but
written as short lines, not curves; kind "polygon").  Should that fail too, the
glyph is left as in the source (metrics and anchors unchanged; kind "source").
Either way it is listed in
the result's ``fallback`` (name -> (kind, error)); ``morph brush`` writes the font
and then names them on one line with exit status 1.

**Metrics and anchors.**  Every swept glyph is shifted right by the nib's left
extent (so it starts no further left of the origin than the original glyph did);
the advance width grows by the nib's width, except for zero-width glyphs
(combining marks), which stay zero-width and are shifted left by the nib's right
extent instead (a mark without an anchor hangs from the end of the preceding,
widened advance: so its centre stays over its base's).  The pen point of the nib,
which draws the glyph's own outline, moves with it to ``t = (shift + nib centre x,
nib centre y)``: GPOS anchors (mark, base, ligature, mark-to-mark, cursive) of
every swept or following glyph move by its ``t``
(:func:`morph.fonts.tables.move_anchors`), so a mark keeps its place relative to
its base whether the mark itself was swept or not (é stays centred).  (Unswept
zero-width marks without an anchor on their base end nib width / 2 to the right.)
Vertical metrics grow by the nib's extent above and below its pen point
(:func:`morph.fonts.tables.grow_vertical_metrics`), OS/2 xAvgCharWidth is
recomputed, and the family is renamed with coherent name IDs
(:func:`morph.fonts.tables.rename_family`).

**Glyph set.**  By default every glyph drawn by its own contours
(:func:`morph.fonts.tables.outline_glyphs`); composites follow (below).

**Composite glyphs** (TrueType; e.g. eacute = e + acute).  A chosen composite is
decomposed and swept as a whole (it becomes a simple glyph, accent brushed too).  A
composite that is not chosen but uses a swept glyph keeps its components (the default
``composites="follow"``): its advance width grows by the nib's width like the swept
base's, and each component that was not swept (the accent) moves by ``t``, i.e. to
where its own swept version would be, so it stays centred over the widened base
(a swept zero-width mark component is moved back by the difference of the two
``t``)
(when every component is swept, the composite *is* the sum of its decomposed
outline: Minkowski sums distribute over unions).  Composites with a scaled / flipped
component or one placed by anchor points cannot follow (the swept outline would be
transformed with its nib, or the point numbers changed): they are decomposed and
swept; ``composites="sweep"`` does that for all of them.  A composite whose
components were not chosen but whose Unicode base letter was (ï = dotlessi +
dieresis when i is chosen) would stay light: its base glyph (its first component,
dotlessi) is swept too, so that it follows; such bases are listed in
``base_not_chosen``.  CFF fonts have no composites; seac accented glyphs are not
handled.

**Variable fonts** are brushed at one instance (``location``, default: the default
instance), made static by :func:`morph.parse.instantiate_font`.
"""

import re
import unicodedata

import numpy as np

from ..budget import plan
from ..errors import ParseError, one_line
from ..nib import (check_convex_nib, convex_region, ellipse_nib,  # noqa: F401 (re-exported)
                   region_extent)
from .jobs import CHUNK, glyph_chunks  # noqa: F401 (re-exported)

__all__ = ["ellipse_nib", "check_convex_nib", "parse_glyph_spec", "brush_font", "composite_plan",
           "region_extent", "sweep_glyph", "sweep_glyphs", "glyph_chunks"]


def parse_glyph_spec(spec):
    """'A-Z,a-z,ampersand,0' -> list of characters / glyph names (ranges of characters)."""
    out = []
    for item in [s.strip() for s in spec.split(",")]:
        if not item:
            continue
        m = re.fullmatch(r"(.)-(.)", item)
        if m and ord(m.group(1)) <= ord(m.group(2)):
            out.extend(chr(c) for c in range(ord(m.group(1)), ord(m.group(2)) + 1))
        else:
            out.append(item)
    return out


def _rigid(component):
    """True for a TrueType component placed by an offset only (no 2x2, no anchor points)."""
    return not hasattr(component, "transform") and getattr(component, "firstPt", None) is None


def composite_plan(font, swept, composites="follow"):
    """Which TrueType composite glyphs depend on the swept glyphs, and how.

    Returns ``(follow, sweep)``: glyph names not in ``swept`` whose components include
    a swept glyph, directly or through other such composites, in dependency order.
    ``follow``: composites that stay composites (see :func:`brush_font`); ``sweep``:
    composites to decompose and sweep themselves -- those with a scaled, rotated or
    flipped component or one placed by anchor points (the swept component's outline
    cannot simply be reused there: (M g) ⊕ nib is not M (g ⊕ nib), and the point
    numbers changed), and all of them with ``composites="sweep"``.  CFF fonts have no
    composites (seac accents are not looked at): both lists are empty.

    Raises:
        ValueError: ``composites`` not "follow" or "sweep".
    """
    if composites not in ("follow", "sweep"):
        raise ValueError("composites must be 'follow' or 'sweep', got %r" % (composites,))
    if "glyf" not in font:
        return [], []
    glyf = font["glyf"]
    comps = {n: glyf[n].components for n in font.getGlyphOrder() if _is_composite(glyf, n)}
    moved = set(swept)
    follow, sweep = [], []
    changed = True
    while changed:  # discovery order is a dependency order
        changed = False
        for n, components in comps.items():
            if n not in moved and any(c.glyphName in moved for c in components):
                moved.add(n)
                changed = True
                rigid = composites == "follow" and all(map(_rigid, components))
                (follow if rigid else sweep).append(n)
    return follow, sweep


def _is_composite(glyf, name):
    """Whether glyph ``name`` of a glyf table is a composite, read from its stored
    header while it is not decoded (decoding every glyph to ask would make the save
    compile every one again, :meth:`morph.fonts.tables.OutlineWriter.saving`)."""
    data = getattr(glyf.glyphs[name], "data", None) if hasattr(glyf, "glyphs") else None
    if data is not None:
        return len(data) >= 2 and int.from_bytes(data[:2], "big", signed=True) < 0
    return glyf[name].isComposite()


def _base_not_chosen(font, swept, planned):
    """Base glyphs to sweep for composites untouched by the plan whose Unicode base
    letter's glyph is swept: ï = dotlessi + dieresis when i is swept but dotlessi is
    not.  Returns {base glyph: [composites]}, the base glyph being the composite's
    first component (followed down to a simple glyph)."""
    if "glyf" not in font:
        return {}
    glyf, cmap = font["glyf"], font.getBestCmap() or {}
    swept, planned = set(swept), set(planned)
    out = {}
    for code, name in sorted(cmap.items()):
        if name in planned or name in swept or not _is_composite(glyf, name):
            continue
        base = unicodedata.normalize("NFD", chr(code))[0]
        if base == chr(code) or cmap.get(ord(base)) not in swept:
            continue
        first = name
        while glyf[first].isComposite():
            first = glyf[first].components[0].glyphName
        if first not in swept:
            out.setdefault(first, []).append(name)
    return out


def _follow_composites(font, follow, moves, extent):
    """Adjust composites that keep their components (TrueType only).

    Each composite grows by the nib's width like its swept components (zero-width
    composites stay so) and moves as a whole by :func:`_pen_move` of its advance, the
    pen point's translation of a swept glyph of that advance; each component, which
    moved by ``moves[component]`` (0 if it was not swept), gets the difference: an
    unswept accent moves to where its own swept version would be, a swept zero-width
    mark (which moved the other way, see :func:`_outline_shift`) comes back over its
    base.  ``moves`` gets the composites' translations.
    """
    if not follow:
        return
    glyf, hmtx = font["glyf"], font["hmtx"]
    for n in follow:
        g = glyf[n]
        adv, _ = hmtx[n]
        tx, ty = _pen_move(adv, extent)
        for c in g.components:
            cx, cy = moves.get(c.glyphName, (0, 0))
            c.x += tx - cx
            c.y += ty - cy
        g.recalcBounds(glyf)
        hmtx[n] = (_new_advance(adv, extent), int(getattr(g, "xMin", 0)))
        moves[n] = (tx, ty)


def _new_advance(adv, extent):
    """The advance of a swept glyph: grown by the nib's width, zero kept zero."""
    return int(round(adv + extent[2] - extent[0])) if adv > 0 else adv


def _outline_shift(adv, extent):
    """x translation of a swept outline: glyph ⊕ nib starts -xmin further left, so it
    moves back; a zero-width mark (hanging left of the pen position, placed after its
    base's advance, which grew by the nib's width) goes the other way, by -xmax."""
    return -extent[0] if adv > 0 else -extent[2]


def _pen_move(adv, extent):
    """The pen point's image (anchors, components) on the integer grid: the nib's
    centre, translated by :func:`_outline_shift`."""
    nx0, ny0, nx1, ny1 = extent
    return (int(round(_outline_shift(adv, extent) + (nx0 + nx1) / 2.0)),
            int(round((ny0 + ny1) / 2.0)))


def _attempts(nib, tol):
    """(kind, sum tolerance, nib) to try in turn, for the geometry share g of
    :func:`morph.budget.plan` (tol): the sum at g; at RETRY_SHARE g; with the nib turned
    by +-delta about its pen point at (1 - TURN_SHARE) g, where delta * (largest
    distance of the nib from its pen point) = TURN_SHARE g, so the outline moves by at
    most g and stays within tol with the export share of the curve conversion."""
    from ..budget import RETRY_SHARE, TURN_SHARE
    from ..region import transform_region

    g = plan(tol).geometry
    yield "exact", g, nib
    yield "retry", RETRY_SHARE * g, nib
    x0, y0, x1, y1 = region_extent(nib)
    radius = float(np.hypot(max(abs(x0), abs(x1)), max(abs(y0), abs(y1))))
    if radius > 0:
        for sign in (1.0, -1.0):
            d = sign * TURN_SHARE * g / radius
            c, s = np.cos(d), np.sin(d)
            yield "rotated", (1.0 - TURN_SHARE) * g, transform_region(
                nib, [[c, -s, 0.0], [s, c, 0.0]])


def sweep_glyph(job):
    """One glyph's outline: (glyph ⊕ nib) shifted, as integer contours, with fallbacks.

    ``job``: ``(name, region, nib, tol, method, offset, quadratic)`` (``tol`` the
    total in font units, half for the sum and half for the curve conversion).
    Returns ``(name, contours, kind, error)``: ``kind`` "exact" (``error`` None),
    "retry" (the sum raised ``error`` and was computed again at a finer tolerance: the
    exact method, curves within tol), "rotated" (computed with the nib turned by a
    tiny angle, see :func:`_attempts`: curves within tol), "polygon" (all raised;
    contours from
    :func:`morph.fonts.jobs.polygon_sum`) or "source" (that failed too: contours
    None, the glyph stays as it is).  Module-level, so it runs in worker processes.
    """
    return _sweep(job)


def _sweep(job, start=0, error=None):
    """:func:`sweep_glyph` from the ``start``-th attempt of :func:`_attempts` on
    (the earlier ones raised ``error``), down the fallback ladder
    (:func:`morph.fonts.jobs.fallback_ladder`: on a MorphError only)."""
    from itertools import islice

    from .jobs import fallback_ladder, polygon_sum, polylines_to_contours

    name, region, nib, tol, method, offset, quadratic = job
    if not region:
        return name, [], "exact", None

    def exact(pen, sum_tol, kind):
        from ..minkowski import minkowski_sum
        from .tables import contours_from_loops

        loops = minkowski_sum(region, pen, sum_tol, method=method)
        # a turned nib's sum is off the exact one by the turn too: the export share
        export = plan(tol).export if kind == "rotated" else _export_tolerance(tol, [(0, loops)])
        return contours_from_loops(loops, export, quadratic, offset, splines=True)

    rungs = [(kind, lambda p=pen, t=sum_tol, k=kind: exact(p, t, k))
             for kind, sum_tol, pen in islice(_attempts(nib, tol), start, None)]
    rungs.append(("polygon", lambda: polylines_to_contours(polygon_sum(region, nib, tol),
                                                           quadratic, offset)))
    kind, contours, error = fallback_ladder(rungs, error)
    if kind is None:
        return name, None, "source", error
    return name, contours, kind, error


def sweep_glyphs(jobs):
    """:func:`sweep_glyph` of several glyphs (a process-pool job), a list of its
    results.  The glyphs are summed together (first attempt, :func:`_first_sums`);
    the outlines of all
    that succeeded are converted in one batch
    (:func:`morph.fonts.tables.contours_from_regions`: the certified fits of all
    glyphs share each round's array calls, a fraction of the glyph-by-glyph cost).
    A glyph whose sum raised goes on with :func:`sweep_glyph`'s next attempts; if
    the batch raises, each glyph is converted alone and a failing one goes on the
    same way, so the results are :func:`sweep_glyph`'s.  Only a MorphError moves a
    glyph down the ladder (:func:`morph.fonts.jobs.fallback_ladder`)."""
    from ..errors import MorphError
    from .jobs import converting, error_text
    from .tables import contours_from_loops, contours_from_regions

    out = [None] * len(jobs)
    for k, job in enumerate(jobs):
        if not job[1]:
            out[k] = (job[0], [], "exact", None)
    done = _first_sums(jobs, [k for k in range(len(jobs)) if out[k] is None], out)
    if done:
        tol, quadratic = jobs[done[0][0]][3], jobs[done[0][0]][6]
        try:
            with converting(len(done)):
                contours = contours_from_regions([loops for _, loops in done],
                                                 _export_tolerance(tol, done), quadratic,
                                                 [jobs[k][5] for k, _ in done], splines=True)
        except MorphError:  # glyph by glyph below
            contours = None
        for i, (k, loops) in enumerate(done):
            name, _, _, tol, _, offset, quadratic = jobs[k]
            if contours is not None:
                out[k] = (name, contours[i], "exact", None)
                continue
            try:
                out[k] = (name, contours_from_loops(loops, _export_tolerance(tol, [(k, loops)]),
                                                    quadratic, offset, splines=True), "exact", None)
            except MorphError as exc:
                out[k] = _sweep(jobs[k], 1, error_text(exc))
    return out


def _export_tolerance(tol, done):
    """The curve conversion's tolerance for the sums ``done`` ([(job index, loops)])
    converted together: what the geometry left of ``tol`` once its error is bounded
    (:meth:`morph.budget.Budget.after` of the largest ``bound`` of the sums: half the
    geometry share where the convolution pieces are exact, as TrueType glyphs ⊕ an
    ellipse's are), so that every outline stays within ``tol``."""
    budget = plan(tol)
    bounds = [loops.bound for _, loops in done]
    if any(b is None for b in bounds):
        return budget.export
    return budget.after(min(max(bounds), budget.geometry))


def _first_sums(jobs, todo, out):
    """[(job index, loops)] of the first attempt of :func:`_attempts` for jobs
    ``todo`` (one nib, tolerance and method): all at once
    (:func:`morph.minkowski.minkowski_sums`), or where that raises a MorphError one
    by one; a glyph whose own sum raised one gets :func:`_sweep`'s next attempts in
    ``out``."""
    from ..errors import MorphError
    from ..minkowski import minkowski_sum, minkowski_sums
    from .jobs import SUM_SHARE, error_text, glyph_progress

    if not todo:
        return []
    _, sum_tol, pen = next(iter(_attempts(jobs[todo[0]][2], jobs[todo[0]][3])))
    method = jobs[todo[0]][4]
    try:
        done = list(zip(todo, minkowski_sums([jobs[k][1] for k in todo], pen, sum_tol,
                                             method=method)))
        glyph_progress(SUM_SHARE * len(todo))
        return done
    except MorphError:  # glyph by glyph below
        pass
    done = []
    for k in todo:
        try:
            done.append((k, minkowski_sum(jobs[k][1], pen, sum_tol, method=method)))
        except MorphError as exc:  # the next attempts
            out[k] = _sweep(jobs[k], 1, error_text(exc))
        glyph_progress(SUM_SHARE)
    return done


def _source_regions(font, names):
    """{name: region} of the glyphs' outlines in font units, read together
    (:func:`morph.parse.read_glyphs`); [] for a glyph without contours (a space: its
    metrics only)."""
    from ..parse import read_glyphs

    return {n: ([] if isinstance(shape, ParseError) else shape.region)
            for n, shape in zip(names, read_glyphs(font, names))}


def open_source(font_path, location=None):
    """The font to brush: a static ``TTFont`` (a variable font at ``location``).

    ``font_path``: a path, a ``TTFont`` (used as it is, and changed by
    :func:`brush_font`), or None for the bundled font.

    Raises:
        ParseError: not a font fontTools can read; a bad location.
    """
    from fontTools.ttLib import TTFont

    from ..parse import default_font_path, instantiate_font
    from .deferred import glyph_list

    glyph_list()   # glyph names made from the character map without fontTools.agl's load
    if hasattr(font_path, "getGlyphSet"):
        font = font_path
    else:
        path = str(default_font_path() if font_path is None else font_path)
        try:
            font = TTFont(path)
            font["head"]
        except Exception as exc:  # fontTools raises many types for garbage input
            raise ParseError("cannot read font %s: %s" % (path, one_line(exc)), path) from exc
    if "fvar" in font or location:
        font = instantiate_font(font, location)
    return font


def brush_font(font_path, out_path, nib_region, glyphs=None, tol=0.5, family_name=None,
               progress=None, method="qac", composites="follow", location=None, jobs=1,
               in_flight=None):
    """Write a copy of the font with each chosen glyph replaced by glyph ⊕ nib.

    ``font_path``: a TrueType (glyf) or CFF OpenType font, a ``TTFont`` (changed in
    place), or None (the bundled font); a variable font is brushed at ``location``
    (dict or "wght=700", default: the default instance).  ``nib_region``: a convex
    region in font units (e.g. :func:`ellipse_nib`).  ``glyphs``: characters or glyph
    names (a chosen composite is decomposed and swept as a whole); None: every glyph
    with an outline.  ``tol``: total outline tolerance in font units (half for the
    sum, half for the curve conversion).  ``family_name``: the new family name
    (default: "<family> Brush").  ``progress(name)`` is called after each swept
    glyph; ``in_flight(units)`` with the glyphs' worth of work reported by chunks in
    flight (:func:`morph.fonts.jobs.run_glyph_jobs`).  ``composites``: "follow" or
    "sweep" (see the module docstring).  ``jobs``:
    processes computing the sums (:func:`morph.fonts.jobs.run_glyph_jobs`; the result does
    not depend on it).  ``out_path``: .ttf/.otf/.woff2/.woff (the flavor; the outline
    format is the source's).

    Returns a dict of statistics: glyphs (chosen, swept), contours, segments,
    followed and decomposed (composites not chosen), base_not_chosen (base glyph ->
    composites: bases swept because the composites' Unicode base letter was chosen),
    anchors (moved), fallback
    (name -> (kind, error) for glyphs that fell back, see the module docstring).

    Raises:
        NibError: a nib that is not one convex loop.
        ParseError: a glyph missing from the font, an unreadable font, a bad location,
            a font without TrueType or CFF outlines.
        ValueError: ``composites`` not "follow" or "sweep"; an output suffix other
            than .ttf, .otf, .woff2, .woff; a variable font not instantiated.
    """
    from .tables import (finish_font, grow_vertical_metrics, move_anchors, outline_writer,
                         rename_family, save_font)

    nib_region = convex_region(nib_region)   # validated: no winding test in the sums
    font = open_source(font_path, location)
    writer = outline_writer(font)
    extent = region_extent(nib_region)
    names, follow, extra, unchosen = _brush_plan(font, glyphs, composites)
    family_name = family_name or _default_family(font)
    chosen = set(names)
    results = _sweep_font(font, names + extra, chosen, nib_region, tol, method,
                          writer.quadratic, jobs, progress, in_flight)
    stats, moves = _store_outlines(font, writer, results, chosen, extent)
    stats.update(followed=len(follow), decomposed=len([n for n in extra if n not in unchosen]),
                 base_not_chosen=unchosen)
    _follow_composites(font, follow, moves, extent)
    stats["anchors"] = move_anchors(font, moves)
    grow_vertical_metrics(font, below=-extent[1], above=extent[3])
    rename_family(font, family_name, tool="morph brush")
    finish_font(font)
    with writer.saving():
        save_font(font, out_path)
    return stats


def written_ink(font):
    """``(cmap, has_ink)`` of a font :func:`brush_font` wrote (the ``TTFont`` it
    changed), as :func:`morph.fonts.specimen.sample_text` takes them, so that the
    sample's choice does not read the written file again: a CFF charstring has ink
    when the bounds the save used are not empty (nothing decoded), any other glyph
    as the specimen tells it (a glyf glyph from its stored header)."""
    from .specimen import _ink_test
    from .cff_encoding import is_bounded

    cmap, has_ink = _ink_test(font)
    if "CFF " not in font:
        return cmap, has_ink
    charstrings = font["CFF "].cff.topDictIndex[0].CharStrings

    def ink(name):
        cs = charstrings[name]
        return cs.bounds is not None if is_bounded(cs) else has_ink(name)
    return cmap, ink


def _sweep_font(font, order, chosen, nib_region, tol, method, quadratic, jobs, progress,
                in_flight):
    """The swept glyphs of ``order`` (:func:`sweep_glyphs` results, in order); each
    outline is moved by :func:`_outline_shift`; ``progress`` is called for the
    ``chosen`` ones.  The source outlines of a chunk of glyphs are read together as
    the chunk is due (:func:`_source_regions`), all before anything is changed (the
    font is changed once every glyph is swept)."""
    from .jobs import run_glyph_jobs

    hmtx = font["hmtx"]
    extent = region_extent(nib_region)

    def jobs_of(names):
        sources = _source_regions(font, names)
        return [(n, sources[n], nib_region, tol, method,
                 (_outline_shift(hmtx[n][0], extent), 0.0), quadratic) for n in names]
    return run_glyph_jobs(sweep_glyphs, order, jobs=jobs, prepare=jobs_of,
                          each=_chosen_progress(progress, chosen), in_flight=in_flight,
                          preload=_WORKER_MODULES + (_QUADRATIC if quadratic else ()))


#: what :func:`sweep_glyphs` imports as it runs (the sums, the curve fitting and its
#: quadrature nodes; cu2qu for TrueType outlines), imported before worker processes
#: are forked so that they share them (:func:`morph.fonts.jobs.preload_modules`)
_WORKER_MODULES = ("morph.minkowski", "morph.fonts.tables", "morph.export",
                   "morph.quadrature")
_QUADRATIC = ("fontTools.cu2qu",)


def _brush_plan(font, glyphs, composites):
    """(names, follow, extra, unchosen): the chosen glyphs (``glyphs`` None: every
    outline glyph), the composites that follow, the glyphs swept besides the chosen
    ones (bases of composites whose Unicode base letter was chosen, then composites
    to decompose) and those bases ({base: [composites]}, :func:`_base_not_chosen`).

    Raises:
        ParseError: a character or name the font lacks.
    """
    from ..parse import glyph_name
    from .tables import outline_glyphs

    if glyphs is None:
        names = outline_glyphs(font)
    else:
        names = list(dict.fromkeys(glyph_name(font, item) for item in glyphs))
    follow, extra = composite_plan(font, names, composites)
    unchosen = _base_not_chosen(font, names, follow + extra)
    if unchosen:  # sweep their base glyphs too, so that they follow
        follow, extra = composite_plan(font, names + list(unchosen), composites)
        extra = list(unchosen) + extra
    return names, follow, extra, unchosen


def _default_family(font):
    """"<family> Brush" from the typographic family name (ID 16) or ID 1."""
    from ..parse.names import name_table

    name = name_table(font, install=True)   # brush_font renames it (rename_family)
    return "%s Brush" % (name.getDebugName(16) or name.getDebugName(1) or "Morph")


def _chosen_progress(progress, chosen):
    """``progress(name)`` for the chosen glyphs, as a :func:`morph.fonts.jobs.
    run_glyph_jobs` callback (``each``)."""
    if progress is None:
        return None

    def report(result):
        if result[0] in chosen:
            progress(result[0])
    return report


def _store_outlines(font, writer, results, chosen, extent):
    """Write the swept outlines and advances; (statistics, moves): glyphs, contours,
    segments (of the chosen glyphs) and fallback (name -> (kind, error)); moves: name
    -> the pen point's translation (:func:`_pen_move`) of every glyph written."""
    hmtx = font["hmtx"]
    stats = {"glyphs": 0, "contours": 0, "segments": 0, "fallback": {}}
    moves = {}
    written = [r for r in results if r[1] is not None]  # None: left as in the source
    advances = {name: _new_advance(hmtx[name][0], extent) for name, *_ in written}
    lsbs = writer.write_many([(name, contours, advances[name]) for name, contours, *_ in written])
    for name, lsb in zip(advances, lsbs):
        moves[name] = _pen_move(hmtx[name][0], extent)
        hmtx[name] = (advances[name], lsb)
    for name, contours, kind, error in results:
        if kind != "exact":
            stats["fallback"][name] = (kind, error)
        if contours is None:
            continue
        if name in chosen:
            stats["glyphs"] += 1
            stats["contours"] += len(contours)
            stats["segments"] += sum(map(len, contours))
    return stats, moves

"""morph.parse.glif: skeleton outlines read straight from .glif data give the same
paths, to the bit, as ufoLib2 and fontTools' pens (morph.parse.ufo.glyph_paths), or
decline the glyph (None) where the pens would mean something else."""

import re

import numpy as np
import pytest
import ufoLib2

from morph.errors import ParseError
from morph.fonts.stream import SkeletonSource
from morph.parse.glif import glif_outline, skeleton_outlines
from morph.parse.ufo import glyph_paths
from tests import RELIEF_SUBSET


def _same_paths(a, b):
    """Equal paths: the same pieces (shape, dtype, every bit) and closed flags."""
    if len(a) != len(b):
        return False
    for (pa, ca), (pb, cb) in zip(a, b):
        if ca != cb or len(pa) != len(pb):
            return False
        for x, y in zip(pa, pb):
            x, y = np.asarray(x), np.asarray(y)
            if x.shape != y.shape or x.dtype != y.dtype or x.tobytes() != y.tobytes():
                return False
    return True


def _components(comps):
    return [(c.baseGlyph, tuple(float(v) for v in tuple(c.transformation))) for c in comps]


def _both(ufo_path, names):
    """(fast, ufoLib2) outlines of the glyphs ``names`` of the UFO at ``ufo_path``."""
    src = SkeletonSource(ufo_path)
    fast = skeleton_outlines([src.glif_data(n) for n in names])
    slow = []
    for n in names:
        g = src[n]
        slow.append((glyph_paths(g), g.components))
    return fast, slow


def _draw(contours, components=()):
    """A draw function: contours as [(points [(x, y, type)])] on a point pen."""
    def draw(pp):
        for points in contours:
            pp.beginPath()
            for x, y, t in points:
                pp.addPoint((x, y), t)
            pp.endPath()
        for base, m in components:
            pp.addComponent(base, m)
    return draw


#: glyphs the fast reader reads: name -> (contours, components)
READ = {
    "open_lines": ([[(0, 0, "move"), (10.5, 3, "line"), (20, -7.25, "line")]], []),
    "open_cubic": ([[(0, 0, "move"), (10, 40, None), (60, 40, None), (70, 0, "curve"),
                     (90, 0, "line")]], []),
    "open_quad": ([[(0, 0, "move"), (50, 100, None), (100, 0, "qcurve")]], []),
    "closed_lines": ([[(0, 0, "line"), (100, 0, "line"), (100, 100, "line"),
                       (0, 100, "line")]], []),
    "closed_dup_end": ([[(0, 0, "line"), (100, 0, "line"), (100, 100, "line"),
                         (0, 0, "line")]], []),
    # starts with off-curve points: read cyclically from the first on-curve point
    "closed_rotated": ([[(10, 40, None), (60, 40, None), (70, 0, "curve"), (0, 0, "line"),
                         (5, -30, "line")]], []),
    "closed_curve_first": ([[(0, 0, "curve"), (0, 50, None), (50, 100, None),
                             (100, 100, "curve"), (100, 50, None), (50, 0, None)]], []),
    "dot": ([[(10, 20, "move")]], []),
    "closed_dot": ([[(10, 20, "line")]], []),
    "zero_pieces": ([[(5, 5, "move"), (5, 5, "line"), (5, 5, "line")]], []),
    "zero_inside": ([[(0, 0, "move"), (10, 0, "line"), (10, 0, "line"), (10, 0, None),
                      (10, 0, None), (10, 0, "curve"), (20, 5, "line")]], []),
    "several": ([[(0, 0, "move"), (1, 1, "line")], [(3, 3, "move")],
                 [(0, 0, "line"), (9, 0, "line"), (9, 9, "line")]],
                [("open_lines", (1, 0, 0, 1, 30, 40)), ("dot", (-1, 0, 0, -1, 0, 0))]),
    "components_only": ([], [("open_quad", (0.5, 0, 0, 0.5, 1.25, 0))]),
    "empty": ([], []),
}

#: glyphs it declines (the pens split or refuse them)
DECLINED = {
    "tt_run": [[(0, 0, "move"), (50, 100, None), (150, 100, None), (200, 0, "qcurve")]],
    "super_cubic": [[(0, 0, "move"), (10, 40, None), (30, 50, None), (60, 40, None),
                     (70, 0, "curve")]],
    "curve_one_off": [[(0, 0, "move"), (10, 40, None), (70, 0, "curve")]],
    "all_off": [[(0, 0, None), (100, 0, None), (100, 100, None)]],
    "huge": [[(0, 0, "move"), (1e300, 0, "line")]],
}


@pytest.fixture(scope="module")
def crafted(tmp_path_factory):
    path = tmp_path_factory.mktemp("glif") / "crafted.ufo"
    font = ufoLib2.Font()
    for name, (contours, components) in READ.items():
        g = font.newGlyph(name)
        _draw(contours, components)(g.getPointPen())
    for name, contours in DECLINED.items():
        g = font.newGlyph(name)
        _draw(contours)(g.getPointPen())
    font.save(path, validate=False)  # the unusual glyphs too
    return path


def test_read_glyphs_are_the_pens_paths(crafted):
    names = list(READ)
    fast, slow = _both(crafted, names)
    for name, f, (paths, comps) in zip(names, fast, slow):
        assert f is not None, name
        assert _same_paths(f[0], paths), name
        assert _components(f[1]) == _components(comps), name


def test_closed_contour_is_read_from_its_first_on_curve_point(crafted):
    (f,), ((paths, _),) = _both(crafted, ["closed_rotated"])
    pieces, closed = f[0][0]
    assert closed and [len(p) for p in pieces] == [2, 2, 4]
    assert np.array_equal(pieces[0][0, :2], [70, 0])    # the first on-curve point
    assert _same_paths(f[0], paths)


def test_unusual_glyphs_are_declined(crafted):
    names = list(DECLINED)
    src = SkeletonSource(crafted)
    assert skeleton_outlines([src.glif_data(n) for n in names]) == [None] * len(names)


@pytest.mark.parametrize("data", [
    b"<glyph name='a' format='1'><outline><contour><point x='0' y='0' type='move'/>"
    b"</contour></outline></glyph>",                                     # format 1
    b"<glyph name='a' format='2'><outline><contour><point x='0' y='0' type='move'/>"
    b"<point x='5' y='0' type='move'/></contour></outline></glyph>",     # move inside
    b"<glyph name='a' format='2'><outline><contour><point x='0' y='0' type='move'/>"
    b"<point x='5' y='0' type='line'/><point x='6' y='1'/></contour></outline></glyph>",
    b"<glyph name='a' format='2'><outline><contour><point x='0' y='0' type='move'/>"
    b"<point x='nan' y='0' type='line'/></contour></outline></glyph>",
    b"<glyph name='a' format='2'><outline><contour><point x='zero' y='0' type='move'/>"
    b"</contour></outline></glyph>",
    b"<glyph name='a' format='2'><outline><contour><point y='0' type='move'/>"
    b"</contour></outline></glyph>",
    b"<glyph name='a' format='2'><outline><thing/></outline></glyph>",
    b"<glyph name='a' format='2'><outline/><outline/></glyph>",
    b"<glyph name='a' format='2'><outline><component/></outline></glyph>",
    b"<glyph name='a' format='2'><outline><contour>",                    # bad XML
    b"<notaglyph format='2'/>",
])
def test_declined_data(data):
    assert skeleton_outlines([data]) == [None]


def test_comments_and_identifiers_do_not_matter():
    data = (b"<?xml version='1.0'?><glyph name='a' format='2'><!-- c --><outline>"
            b"<contour identifier='c1'><!-- c --><point x='0' y='0' type='move' name='n'/>"
            b"<point x='3' y='4' type='line' smooth='no' identifier='p1'/></contour>"
            b"</outline></glyph>")
    (paths, comps), = skeleton_outlines([data])
    (pieces, closed), = paths
    assert not closed and comps == []
    assert np.array_equal(pieces[0], [[0, 0, 1], [3, 4, 1]])
    assert glif_outline(data) is not None


def test_relief_subset_is_read_the_same(tmp_path):
    src = SkeletonSource(RELIEF_SUBSET)
    names = src.keys()
    fast, slow = _both(RELIEF_SUBSET, names)
    assert all(f is not None for f in fast)
    for name, f, (paths, comps) in zip(names, fast, slow):
        assert _same_paths(f[0], paths), name
        assert _components(f[1]) == _components(comps), name


def _outline_rows(outlines):
    return [None if o is None else ([(len(ps), closed, [np.asarray(p).tobytes() for p in ps])
                                     for ps, closed in o[0]], _components(o[1]))
            for o in outlines]


def test_scan_trusts_the_shells_plain_markup_of_the_same_bytes(tmp_path):
    """The shells' reader marks the glyphs whose markup but the outline is plain GLIF
    2 (light_ufo.glif_shell); the outline scan does not parse those again: the same
    outlines as a scan that parses every file.  A glyph whose rest is not plain is
    not marked; a file changed after the shells were read (another hash) is parsed
    again, and a format the scan refuses is then refused."""
    import shutil

    ufo = tmp_path / "s.ufo"
    shutil.copytree(RELIEF_SUBSET, ufo)
    folder = ufo / "glyphs"
    o = (folder / "o.glif").read_bytes()
    o, n = re.subn(rb'<advance width="([0-9]+)"', rb"<advance width='\1'", o)
    assert n == 1
    (folder / "o.glif").write_bytes(o)                                  # not plain
    (folder / "i.glif").write_bytes((folder / "i.glif").read_bytes().replace(
        b'format="2"', b'format="2.0"', 1))                            # the scan refuses it
    src = SkeletonSource(ufo, light=True)
    src.shell_font()
    names = src.keys()
    assert "o" not in src._plain and "i" not in src._plain
    assert len(src._plain) == len(names) - 2
    parsed = skeleton_outlines([src.glif_data(n) for n in names])
    assert sum(o is not None for o in parsed) > 10
    assert _outline_rows(src.skeleton_outlines(names)) == _outline_rows(parsed)
    a = folder / "a.glif"
    a.write_bytes(a.read_bytes().replace(b'format="2"', b'format="3"', 1))
    fresh = skeleton_outlines([a.read_bytes()])
    assert fresh == [None]   # format 3: declined (the caller's ufoLib2 reads or refuses it)
    assert src.skeleton_outlines(["a"]) == fresh
    trusted = skeleton_outlines([a.read_bytes()], [True])   # the mark, were it trusted
    assert trusted != fresh


def test_stroke_work_falls_back_to_ufolib2(crafted):
    """The stroke's jobs: a declined glyph is read by ufoLib2 (same paths as the
    pens), a read one by the array reader."""
    from morph.fonts.stroke import _stroke_work

    src = SkeletonSource(crafted)
    names = ["open_cubic", "tt_run", "super_cubic", "closed_rotated"]
    work = _stroke_work(src, names, {}, None, None, {n: 0 for n in names}, None)
    for name, job in zip(names, work):
        assert _same_paths(job[1], glyph_paths(src[name])), name
    with pytest.raises(ParseError, match="glyph 'huge' has a coordinate"):
        _stroke_work(src, ["open_cubic", "huge"], {}, None, None, {"open_cubic": 0, "huge": 0},
                     None)


def _scan_agrees(datas):
    """The byte scan's outlines (:mod:`morph.parse._glif_scan`) of ``datas``: where it
    reads a glyph, the XML reader's result to the bit; the indices it reads."""
    from morph.parse._glif_scan import scan_outlines
    from morph.parse.glif import _tree_outlines

    fast, left = scan_outlines(datas)
    tree = _tree_outlines(datas)
    read = [i for i, f in enumerate(fast) if f is not None]
    assert sorted(read + left) == [i for i, d in enumerate(datas) if d is not None]
    for i in read:
        assert tree[i] is not None, i
        assert _same_paths(fast[i][0], tree[i][0]), i
        assert _components(fast[i][1]) == _components(tree[i][1]), i
    return read


def _ufo_datas(path):
    src = SkeletonSource(path)
    return [src.glif_data(n) for n in src.keys()]


def test_scan_reads_the_test_data_as_the_xml_reader(crafted):
    import os

    ufos = [RELIEF_SUBSET, crafted]
    cache = os.environ.get("MORPH_BENCH_CACHE")   # the bench's skeleton UFOs, where present
    if cache and os.path.isdir(cache):
        ufos += sorted(os.path.join(cache, f) for f in os.listdir(cache) if f.endswith(".ufo"))
    for ufo in ufos:
        datas = _ufo_datas(ufo)
        read = _scan_agrees(datas)   # composites too
        assert set(read) >= set(range(len(datas))) - {
            i for i, d in enumerate(datas) if skeleton_outlines([d]) == [None]}, ufo
        assert any(b"<component" in datas[i] for i in read) or ufo != RELIEF_SUBSET


_PLAIN = (b"<?xml version='1.0' encoding='UTF-8'?>\n<glyph name=\"a\" format=\"2\">\n"
          b"  <advance width=\"500\"/>\n  <outline>\n    <contour>\n"
          b"      <point x=\"0\" y=\"0\" type=\"move\"/>\n"
          b"      <point x=\"10\" y=\"40\"/>\n      <point x=\"60\" y=\"40\"/>\n"
          b"      <point x=\"70.5\" y=\"-3e1\" type=\"curve\" smooth=\"yes\"/>\n"
          b"    </contour>\n  </outline>\n</glyph>\n")


@pytest.mark.parametrize("old, new, scanned", [
    (b"", b"", True),
    (b'<contour>', b'<contour identifier="c1">', True),
    (b'smooth="yes"/>', b'smooth="yes" name="p" identifier="i1"/>', True),
    (b'<advance width="500"/>', b'<anchor x="1" y="2" name="top"/><guideline y="3"/>'
     b'<lib><dict><key>k</key><string>&lt;v&gt;</string></dict></lib>', True),
    (b'</outline>', b'</outline><!-- a comment --><note>n &amp; m</note>', True),
    (b'<point x="0" y="0" type="move"/>', b"<point x='0' y='0' type='move'/>", False),
    (b'<point x="0" y="0" type="move"/>', b'<point y="0" x="0" type="move"/>', False),
    (b'<point x="0" y="0" type="move"/>', b'<point type="move" x="0" y="0"/>', False),
    (b'<point x="10" y="40"/>', b'<!-- c --><point x="10" y="40"/>', False),
    (b'<point x="10" y="40"/>', b'<point x="1&#48;" y="40"/>', False),
    (b'<point x="10" y="40"/>', b'<point x="10" y="40" name="a&lt;b"/>', False),
    (b'<point x="10" y="40"/>', b'<point x="10" y="40" name="a<b"/>', False),
    (b'<point x="10" y="40"/>', b'<point x="10" y="40"><![CDATA[x]]></point>', False),
    (b'<point x="10" y="40"/>', b'<point x="10" y="40" y="41"/>', False),
    (b'<point x="10" y="40"/>', b'<point x="10" y="40" name="\xc3\xa9"/>', False),
    (b'<point x="10" y="40"/>', b'text<point x="10" y="40"/>', False),
    (b'</contour>', b'</contour><contour/>', True),
    (b'</contour>', b'</contour>\n  </outline><outline>', False),
    (b'</contour>', b'', False),                                    # not well-formed
    (b'<advance width="500"/>', b'<advance width="500">', False),  # not well-formed
    (b'format="2"', b'format="1"', False),
    (b'</contour>', b'</contour><component base="b" xOffset="5" yScale="-1.5"/>', True),
    (b'  <outline>\n', b'  <outline>\n<component base="b" identifier="c"/>\n', True),
    (b'</contour>', b'</contour><component base="b" xScale=""/>', True),
    (b'</contour>', b'<component base="b"/></contour>', False),     # inside a contour
    (b'</contour>', b'</contour><component xOffset="1"/>', False),   # no base
    (b'</contour>', b'</contour><component base="b" xOffset="a"/>', False),
    (b'</contour>', b'</contour><component base="b"><x/></component>', False),
    (b'</contour>', b"</contour><component base='b'/>", False),
    (b'</contour>', b'</contour><component base="b" base="c"/>', False),
])
def test_scan_reads_or_leaves_each_form(old, new, scanned):
    """An edit of a plain file: the scan reads it (the same paths as the XML
    reader) or leaves it to that reader, as expected."""
    data = _PLAIN.replace(old, new, 1)
    assert data != _PLAIN or not old
    assert bool(_scan_agrees([data])) == scanned
    assert skeleton_outlines([data]) == [None] or _same_paths(
        skeleton_outlines([data])[0][0], glif_outline(data) and _tree_paths(data))


def _tree_paths(data):
    from morph.parse.glif import _tree_outlines

    return _tree_outlines([data])[0][0]


def test_scan_reads_several_glyphs_and_leaves_the_odd_one():
    odd = _PLAIN.replace(b'<point x="10" y="40"/>', b"<point x='10' y='40'/>")
    datas = [_PLAIN, odd, None, _PLAIN.replace(b"70.5", b"1e400"), _PLAIN]
    assert _scan_agrees(datas) == [0, 4]
    # a glyph whose first point is odd: the text it shares with the glyph before
    # is refused, and both are left to the XML reader
    odd = _PLAIN.replace(b'<point x="0" y="0" type="move"/>', b"<point x='0' y='0'/>")
    assert _scan_agrees([_PLAIN, odd, _PLAIN, _PLAIN]) == [2, 3]


def _element_rows(el):
    """(tag, attributes, text, children) of an element, recursively: what the GLIF
    readers read of it."""
    return (el.tag, dict(el.attrib), el.text, [_element_rows(c) for c in el])


_PLAIN_HEAD = b"<?xml version='1.0' encoding='UTF-8'?>\n"


@pytest.mark.parametrize("data, plain", [
    (_PLAIN_HEAD + b'<glyph name="A" format="2">\n  <advance width="567.0"/>\n'
     b'  <unicode hex="0041"/>\n  <anchor x="1" y="2" name="top"/>\n  <outline/>\n</glyph>\n',
     True),
    (b'<?xml version="1.0" encoding="UTF-8"?><glyph name="a&gt;" format="2"/>', False),
    (b'<glyph name="a" format="2"><advance width="1" /></glyph>', True),
    (b' \n<glyph name="a"></glyph>', True),
    (b"<glyph name='a'></glyph>", False),                     # single quotes
    (b'<glyph name="a">x<advance width="1"/></glyph>', False),  # text
    (b'<glyph name="a"><!-- c --></glyph>', False),             # a comment
    (b'<glyph name="a b\tc"></glyph>', False),                  # a value XML normalizes
    (b'<glyph name="a>b"></glyph>', False),
    (b'<glyph name="\xc3\xa9"></glyph>', False),                # outside ASCII
    (b'<glyph name="a"><lib><dict/></lib></glyph>', False),     # nested
    (b'<glyph name = "a"></glyph>', False),
    (b'<glyph name="a"/>', False),
])
def test_plain_markup_is_read_as_elementtree_reads_it(data, plain):
    """morph.parse.glif_xml.plain_tree reads ufoLib's plain markup (no XML parser) into
    the tags, attributes and texts ElementTree gives, and leaves anything else to
    the parser (None)."""
    import xml.etree.ElementTree as ET

    from morph.parse.glif_xml import plain_tree

    tree = plain_tree(data)
    assert (tree is not None) == plain
    if plain:
        assert _element_rows(tree) == _element_rows(ET.fromstring(data))


@pytest.mark.parametrize("data", [
    b'<glyph name="a" name="b"></glyph>',                     # a repeated attribute
    b'<glyph name="a"><advance width="1"height="2"/></glyph>',  # no space between
    b'<glyph name="a"></glyph><glyph name="b"></glyph>',        # two roots
    b' <?xml version="1.0" encoding="UTF-8"?><glyph name="a"></glyph>',
    b'<glyph name="a"><advance width="1"></glyph>',             # not closed
    b'<glyph name="a"><advance width="/></glyph>',              # a value not closed
    b'<glyph name="a"><"x"/></glyph>',                          # no name
])
def test_plain_markup_leaves_what_is_not_well_formed_to_the_parser(data):
    """What ElementTree refuses is not read as plain either (the parser then names
    the error)."""
    import xml.etree.ElementTree as ET

    from morph.parse.glif_xml import plain_tree

    with pytest.raises(ET.ParseError):
        ET.fromstring(data)
    assert plain_tree(data) is None


def test_plain_markup_of_the_relief_subset_is_elementtree_s():
    """Every .glif of the Relief subset, its outline cut out as the shell and scan
    readers cut it: read as plain, the same elements as ElementTree's (the
    comparison fails on a changed attribute)."""
    import xml.etree.ElementTree as ET

    from morph.parse.glif_xml import plain_tree

    read = 0
    for path in sorted((RELIEF_SUBSET / "glyphs").glob("*.glif")):
        data = path.read_bytes()
        a, b = data.find(b"<outline"), data.find(b"</outline>")
        rest = data[:a] + b"<outline/>" + data[b + 10:] if a >= 0 <= b else data
        tree = plain_tree(rest)
        if tree is not None:
            read += 1
            assert _element_rows(tree) == _element_rows(ET.fromstring(rest))
            changed = rest.replace(b'width="', b'width="1', 1)
            if changed != rest:
                assert _element_rows(plain_tree(changed)) != _element_rows(ET.fromstring(rest))
    assert read > 10


def _shell_rows(data, monkeypatch, xml_only):
    """What morph.parse.light_ufo.glif_shell reads of ``data`` (its glyph's lib,
    components and contours, or the NotLight it raises), with the plain readers of
    libs and components or (``xml_only``) the XML parser alone."""
    from morph.parse import light_ufo

    with monkeypatch.context() as m:
        if xml_only:
            m.setattr(light_ufo, "plain_lib", lambda data: None)
            m.setattr(light_ufo, "plain_components", lambda outline: None)
        try:
            glyph, contours = light_ufo.glif_shell("a", data)
        except light_ufo.NotLight:
            return "NotLight"
    return (repr(glyph.lib), [(c.baseGlyph, c.transformation, c.identifier)
                              for c in glyph.components], contours, glyph.width)


_LIB_GLYPH = (b"<?xml version='1.0' encoding='UTF-8'?>\n<glyph name=\"a\" format=\"2\">\n"
              b'  <advance width="500"/>\n%s</glyph>\n')


@pytest.mark.parametrize("lib, plain", [
    (b"<lib><dict><key>k</key><string>v</string></dict></lib>", True),
    (b"<lib>\n <dict>\n  <key>a.b</key>\n  <array><integer>1</integer><real>2.5</real>"
     b"</array>\n  <key>c</key><true/></dict>\n </lib>\n", True),
    (b"<lib><dict><key>k</key><string>x &amp; &lt;y&gt; &quot;</string></dict></lib>", True),
    (b"<lib><dict><key>k</key><string>&#233; &#13;</string></dict></lib>", False),
    (b"<lib><dict><key>k</key><string>\xc3\xa9t\xc3\xa9</string></dict></lib>", True),
    (b"<lib><dict><key>public.markColor</key><string>1,0,0,1</string></dict></lib>", True),
    (b"<lib><dict><key>k</key><string>\xe9</string></dict></lib>", False),   # not UTF-8
    (b"<lib><dict/></lib>", False),
    (b"<lib><dict></dict><dict></dict></lib>", False),                   # two dicts
    (b"<lib><dict></dict><foo/><dict></dict></lib>", False),
    (b"<lib><dict></dict><foo/></lib>", False),                          # another child
    (b"<lib><dict></dict></array><array><dict></dict></lib>", False),    # not well-formed
    (b"<lib><dict></dict></lib></lib><lib><dict></dict></lib>", False),
    (b"<lib>text<dict></dict></lib>", False),
    (b"<lib><!-- c --><dict></dict></lib>", False),                      # a comment
    (b"<lib><dict><key>k</key><string><![CDATA[x]]></string></dict></lib>", False),
    (b'<lib><dict xmlns="urn:x"></dict></lib>', False),                  # a namespace
    (b"<lib><a:dict></a:dict></lib>", False),
    (b'<lib a="1"><dict></dict></lib>', False),                          # attributes
    (b"<lib><dict><key>k</key></dict></lib>", False),                    # no value
    (b"<lib><dict><key>k</key><string>&foo;</string></dict></lib>", False),
    (b"<lib><dict><key>k</key><string>a</string></dict></lib><lib><dict></dict></lib>",
     False),                                                             # two libs
    (b"<lib><dict><key>k</key><string>a</strin></dict></lib>", False),    # not well-formed
    (b"<lib><dict><key>k</key><string>a</string></dict></lib><note>n</note>", True),
    (b"<lib><dict><key>com.github.fonttools.x</key><true/></dict></lib>", True),
])
def test_plain_lib_is_read_as_the_xml_reader_reads_it(lib, plain, monkeypatch):
    """A glyph's lib in plain markup is read by plistlib from its bytes
    (morph.parse.glif_xml.plain_lib), the rest of the file without the XML parser:
    the same lib as the XML parser's tree gives, the same refusals (NotLight);
    anything else is left to the XML parser."""
    from morph.parse.glif_xml import plain_lib

    data = _LIB_GLYPH % lib
    assert (plain_lib(data) is not None) == plain
    assert _shell_rows(data, monkeypatch, False) == _shell_rows(data, monkeypatch, True)
    if plain and _shell_rows(data, monkeypatch, True) != "NotLight":   # it sees a change
        changed = data.replace(b"</dict>", b"<key>z</key><string>z</string></dict>", 1)
        assert _shell_rows(changed, monkeypatch, False) != _shell_rows(data, monkeypatch, True)


def _libs_read_together(datas):
    """The libs of glyphs ``datas`` read as morph.parse.light_ufo.read_light_font
    reads them (plain libs in one parse), or "NotLight"."""
    from morph.parse import light_ufo

    pending, glyphs = [], []
    try:
        glyphs = [light_ufo.glif_shell("a", d, pending)[0] for d in datas]
        light_ufo._read_libs(pending)
    except light_ufo.NotLight:
        return "NotLight"
    return [repr(g.lib) for g in glyphs]


@pytest.mark.parametrize("bad", [
    b"",
    b"<lib><dict><key>k</key></dict></lib>",                             # plistlib refuses
    b"<lib><dict></dict><dict></dict></lib>",                            # two dicts
    b"<lib><dict><key>k</key><string>a</strin></dict></lib>",             # not well-formed
    b"<lib><dict><key>com.github.fonttools.x</key><true/></dict></lib>",  # a key refused
])
def test_plain_libs_are_read_together_as_each_alone(bad, monkeypatch):
    """The plain libs of a font's glyphs, read in one parse, are those each read
    alone gives (and a glyph plistlib does not read is read whole, alone)."""
    libs = [b"<lib><dict><key>k</key><string>v%d</string></dict></lib>" % k for k in range(3)]
    datas = [_LIB_GLYPH % lib for lib in libs[:2] + [bad] + libs[2:]]
    alone = [_shell_rows(d, monkeypatch, True) for d in datas]
    together = _libs_read_together(datas)
    assert together == ("NotLight" if "NotLight" in alone else [a[0] for a in alone])
    assert together != _libs_read_together(datas[::-1]) or together == "NotLight"


@pytest.mark.parametrize("outline, plain", [
    (b'<outline><component base="b"/><component base="c" xOffset="10" yScale="-1"/>'
     b"</outline>", True),
    (b'<outline>\n <contour>\n  <point x="1" y="2" type="move"/>\n  <point x="3" y="4" '
     b'type="line"/>\n </contour>\n <component base="b" identifier="i"/>\n <contour/>\n'
     b"</outline>", True),
    (b'<outline><component base="b" xScale="0.5e1"/></outline>', True),
    (b'<outline><component base="b" foo="1"/></outline>', True),        # refused alike
    (b'<outline><component xOffset="1"/></outline>', True),
    (b'<outline><component base=""/></outline>', True),
    (b'<outline><component base="b"><x/></component></outline>', False),  # children
    (b'<outline><component base="b" base="c"/></outline>', False),      # not well-formed
    (b'<outline><contour><component base="b"/></contour></outline>', False),
    (b'<outline><contour><point x="1" y="2"></contour><component base="b"/></outline>',
     False),
    (b'<outline><component base="b"/></contour></outline>', False),
    (b'<outline><component base="a&amp;b"/></outline>', False),          # a reference
    (b"<outline><component base='b'/></outline>", False),                # single quotes
    (b'<outline>x<component base="b"/></outline>', False),               # text
    (b'<outline><component base="b"/><contour></outline>', False),       # not closed
    (b'<outline><component base="b\tc"/></outline>', False),
])
def test_plain_components_are_read_as_the_xml_reader_reads_them(outline, plain, monkeypatch):
    """The components of an outline in plain markup are read without the XML parser
    (morph.parse.glif_xml.plain_components): the same components, the same
    refusals (NotLight) as the XML parser's tree; anything else is left to it."""
    from morph.parse.glif_xml import plain_components

    data = _LIB_GLYPH % outline
    assert (plain_components(outline[:-len(b"</outline>")]) is not None) == plain
    assert _shell_rows(data, monkeypatch, False) == _shell_rows(data, monkeypatch, True)
    if plain and _shell_rows(data, monkeypatch, True) != "NotLight":   # it sees a change
        changed = data.replace(b'base="b"', b'base="d"', 1)
        assert _shell_rows(changed, monkeypatch, False) != _shell_rows(data, monkeypatch, True)


@pytest.mark.parametrize("text", ["1", "-0", "+4", " 3 ", "1_000", "007", "1.5", "1.", ".5",
                                  "-2.25e3", "1e5", "nan", "inf", "\u0661\u0662", "1.2.3",
                                  "abc", ""])
def test_glif_number_is_int_else_float(text):
    """glif_number reads a text as glifLib does: int where int takes it, else float
    (the same value and type, or the same refusal)."""
    from morph.parse.glif_xml import glif_number

    def reference(t):
        try:
            return int(t)
        except ValueError:
            return float(t)

    try:
        want = reference(text)
    except ValueError:
        with pytest.raises(ValueError):
            glif_number(text)
        return
    got = glif_number(text)
    assert type(got) is type(want) and (got == want or (got != got and want != want))

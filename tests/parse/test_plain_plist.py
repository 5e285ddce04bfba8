"""The plain plist reader (morph.parse.plain_plist) against plistlib, its oracle."""

import glob
import os
import plistlib
import random

import pytest

from morph.parse.plain_plist import load_plist, plain_plist

HERE = os.path.dirname(os.path.dirname(__file__))
HEAD = (b'<?xml version="1.0" encoding="UTF-8"?>\n<!DOCTYPE plist PUBLIC "-//Apple//DTD '
        b'PLIST 1.0//EN" "http://www.apple.com/DTDs/PropertyList-1.0.dtd">\n'
        b'<plist version="1.0">\n')


def same(a, b):
    """Equal values of equal types (True is not 1, 1.0 is not 1), dicts in the same
    order, floats to the bit."""
    if type(a) is not type(b):
        return False
    if isinstance(a, dict):
        return list(a) == list(b) and all(same(a[k], b[k]) for k in a)
    if isinstance(a, list):
        return len(a) == len(b) and all(same(x, y) for x, y in zip(a, b))
    if isinstance(a, float):
        return a.hex() == b.hex()
    return a == b


def plist(body):
    return HEAD + body.encode("utf-8") + b"\n</plist>\n"


@pytest.mark.parametrize("body", [
    "<dict><key>a</key><string>x &amp; y &lt;z&gt; &quot;q&quot; &apos;</string></dict>",
    "<dict><key/><string/><key>b</key><dict/><key>c</key><array/></dict>",
    "<array><integer>-0</integer><integer>12345678901234567890</integer>"
    "<real>-0</real><real>5</real><real>0.1</real><real>-1234.5678</real></array>",
    "<array>\n\t<true/>\n\t<false/>\n\t<string> a, b: {c} [d] \\e \"f\" \t\n</string></array>",
    "<dict><key>k</key><string>é ß 😀</string><key>k</key><integer>2</integer></dict>",
    "<array><array><dict><key>x</key><array><string>]</string></array></dict></array></array>",
    "<string>just a string</string>",
])
def test_plain_matches_plistlib(body):
    data = plist(body)
    got = plain_plist(data)
    assert got is not None
    assert same(got, plistlib.loads(data))


@pytest.mark.parametrize("body", [
    "<array><integer>1</integer>2</array>",     # text plistlib ignores: JSON would read it
    "<array><integer>1</integer>true</array>",
    "<array>7<integer>5</integer></array>",
    "<array>-<real>5.0</real></array>",
    "<dict><key>a</key>x<string>y</string></dict>",
    "<array><integer>0x1F</integer></array>",   # hexadecimal: plistlib's
    "<array><integer>007</integer></array>",
    "<array><real>1e5</real></array>",
    "<array><real> 1.5</real></array>",
    "<array><data>AAAA</data></array>",
    "<array><!-- c --><true/></array>",
    "<array><true></true></array>",
    "<array><string>&#65;</string></array>",
    "<dict><key>a</key></dict>",                # a key without a value
    "<dict><string>a</string></dict>",
    "<array><key>a</key><string>a</string></array>",
    "<string>a</string><string>b</string>",
    "<array><string a=\"1\">x</string></array>",
    "<array><string>a\rb</string></array>",
    "<array><key>a</string></array>",           # not well-formed: expat refuses it
    "<array><string>a</key></array>",
    "<array><string>a</string></string></array>",
    "<array><string>a</string></integer></array>",
    "<dict><key>a</key><dict></array></dict>",
    "<dict><string>a</key><key>b</string></dict>",
])
def test_plain_declines(body):
    """What plistlib ignores, converts otherwise or refuses is left to it."""
    assert plain_plist(plist(body)) is None


def test_declines_other_heads():
    body = "<array><true/></array>\n</plist>\n"
    for head in (b'<?xml version="1.0" encoding="UTF-16"?>\n<plist version="1.0">',
                 b'\xef\xbb\xbf<?xml version="1.0" encoding="UTF-8"?>\n<plist version="1.0">',
                 b'<plist version="1.0">'):
        assert plain_plist(head + body.encode()) is None
    assert plain_plist(HEAD + body.encode() + b"junk") is None
    assert same(plain_plist(HEAD + body.encode()), [True])


def _random_value(rng, depth=0):
    kind = rng.randrange(8 if depth < 3 else 5)
    if kind == 0:
        return rng.randrange(-10 ** rng.randrange(1, 19), 10 ** rng.randrange(1, 19))
    if kind == 1:
        return rng.uniform(-1e6, 1e6) * 10.0 ** rng.randrange(-5, 5)
    if kind == 2:
        return rng.random() < 0.5
    if kind in (3, 4):
        return _random_text(rng)
    if kind == 5:
        return [_random_value(rng, depth + 1) for _ in range(rng.randrange(4))]
    return {_random_text(rng) if rng.random() < 0.9 else "": _random_value(rng, depth + 1)
            for _ in range(rng.randrange(4))}


def _random_text(rng):
    return "".join(rng.choice("ab, :{}[]\"'\\&<>\t\né😀 ") for _ in range(rng.randrange(6)))


def test_random_plists():
    """plistlib's own writing of random values (floats as repr, strings escaped),
    read plain: plistlib's values, or declined; and text dropped between elements
    is declined or read as plistlib reads it."""
    rng = random.Random(5)
    read = 0
    for _ in range(400):
        value = {"v": _random_value(rng)}
        data = plistlib.dumps(value, sort_keys=False)
        got = plain_plist(data)
        if got is not None:
            read += 1
            assert same(got, plistlib.loads(data))
        cut = rng.randrange(len(data))
        at = data.find(b">", cut)
        if at > 0:
            noisy = data[:at + 1] + rng.choice([b"1", b"true", b" 2 ", b"x", b"-"]) + data[at + 1:]
            try:
                ref = plistlib.loads(noisy)
            except Exception:  # noqa: BLE001 - expat's and plistlib's errors: refused
                ref = None
            got = plain_plist(noisy)
            assert got is None or (ref is not None and same(got, ref))
    assert read > 300


def test_files_read_as_plistlib_reads_them():
    files = glob.glob(os.path.join(HERE, "data", "**", "*.plist"), recursive=True)
    assert files
    for path in files:
        with open(path, "rb") as f:
            ref = plistlib.load(f)
        assert same(load_plist(path), ref)

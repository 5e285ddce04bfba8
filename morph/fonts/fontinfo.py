"""The OpenType values of a UFO's font info, with ufo2ft's fallbacks (ufo2ft 3's
``fontInfoData``; MIT licence): :func:`info_value` is ufo2ft's
``getAttrWithFallback``, with the style map, PostScript names, dates, version and
the other derived values it falls back on, and :func:`full_name` (name ID 4).

Plain values of the info object, imported by what writes tables from it without
ufo2ft: the static compiler (:mod:`morph.fonts.tables_static`), the UFO's tables of a
brushed font (:mod:`morph.fonts.ufo_tables`), the command's report
(:mod:`morph.cli.fonts`).  It imports nothing of morph and only the standard
library, so any of them may import it at its top.
"""

import math
import os
import time

__all__ = ["info_value", "full_name", "normalize_for_postscript"]

def _upm(info):
    return info_value(info, "unitsPerEm")


def _ot_round(value):
    return int(math.floor(value + 0.5))


_STYLE_MAP = ("regular", "bold", "italic", "bold italic")
_DATE_FORMAT = "%Y/%m/%d %H:%M:%S"


def _date_now():
    return time.strftime(_DATE_FORMAT, time.gmtime())


def _created(info):
    if "SOURCE_DATE_EPOCH" in os.environ:
        from datetime import datetime, timezone

        t = datetime.fromtimestamp(int(os.environ["SOURCE_DATE_EPOCH"]), timezone.utc)
        return t.strftime(_DATE_FORMAT)
    return _date_now()


def _style_map_family(info):
    family = info_value(info, "openTypeNamePreferredFamilyName")
    style = info.styleMapStyleName
    if not style:
        style = info_value(info, "openTypeNamePreferredSubfamilyName")
    if style is None or style.lower() in _STYLE_MAP:
        style = ""
    return (family + " " + style).strip()


def _style_map_style(info):
    style = info_value(info, "openTypeNamePreferredSubfamilyName")
    if style is None or style.strip().lower() not in _STYLE_MAP:
        return "regular"
    return style.strip().lower()


def _slope_rise(info):
    angle = info_value(info, "italicAngle")
    if angle != 0 and getattr(info, "openTypeHheaCaretSlopeRun", None) is not None:
        return _ot_round(info.openTypeHheaCaretSlopeRun / math.tan(math.radians(-angle)))
    return _upm(info)


def _slope_run(info):
    angle = info_value(info, "italicAngle")
    if angle != 0:
        rise = info_value(info, "openTypeHheaCaretSlopeRise")
        return _ot_round(math.tan(math.radians(-angle)) * rise)
    return 0


def _name_version(info):
    return "Version %d.%s" % (info_value(info, "versionMajor"),
                              str(info_value(info, "versionMinor")).zfill(3))


def _unique_id(info):
    version = info_value(info, "openTypeNameVersion").replace("Version ", "")
    return "%s;%s;%s" % (version, info_value(info, "openTypeOS2VendorID"),
                         info_value(info, "postscriptFontName"))


def _typo_line_gap(info):
    return max(int(_upm(info) * 1.2) - info_value(info, "ascender")
               + info_value(info, "descender"), 0)


_PS_EXCEPTIONS = set("[](){}<>/%")
_PS_ALLOWED = {chr(i) for i in range(33, 127)}


def normalize_for_postscript(s, allow_spaces=True):
    """ufo2ft's ``normalizeStringForPostscript``."""
    import unicodedata

    out = []
    for c in s:
        if c == " " and not allow_spaces:
            continue
        if c in _PS_EXCEPTIONS:
            continue
        if c not in _PS_ALLOWED:
            c = unicodedata.normalize("NFKD", c)
            if not set(c) < _PS_ALLOWED:
                c = c.encode("ascii", errors="replace").decode()
        out.append(c)
    return "".join(out)


def _ps_font_name(info):
    return normalize_for_postscript("%s-%s" % (
        info_value(info, "openTypeNamePreferredFamilyName"),
        info_value(info, "openTypeNamePreferredSubfamilyName")), allow_spaces=False)


def _blue_scale(info):
    zone = 0
    for blues in (info_value(info, "postscriptBlueValues"),
                  info_value(info, "postscriptOtherBlues")):
        if blues:
            for x, y in zip(blues[:-1:2], blues[1::2]):
                zone = max(zone, abs(y - x))
    return 3 / (4 * zone) if zone else 0.039625


_STATIC = dict(
    versionMajor=0, versionMinor=0, copyright=None, trademark=None, familyName="New Font",
    styleName="Regular", unitsPerEm=1000, italicAngle=0, year=None, note=None,
    openTypeHeadLowestRecPPEM=6, openTypeHeadFlags=[0, 1], openTypeHheaLineGap=0,
    openTypeHheaCaretOffset=0, openTypeNameDesigner=None, openTypeNameDesignerURL=None,
    openTypeNameManufacturer=None, openTypeNameManufacturerURL=None,
    openTypeNameLicense=None, openTypeNameLicenseURL=None, openTypeNameDescription=None,
    openTypeNameCompatibleFullName=None, openTypeNameSampleText=None,
    openTypeNameRecords=[], openTypeOS2WidthClass=5, openTypeOS2WeightClass=400,
    openTypeOS2Selection=[], openTypeOS2VendorID="NONE",
    openTypeOS2Panose=[0, 0, 0, 0, 0, 0, 0, 0, 0, 0], openTypeOS2FamilyClass=[0, 0],
    openTypeOS2UnicodeRanges=None, openTypeOS2CodePageRanges=None, openTypeOS2Type=[2],
    openTypeOS2SubscriptXSize=None, openTypeOS2SubscriptYSize=None,
    openTypeOS2SubscriptXOffset=None, openTypeOS2SubscriptYOffset=None,
    openTypeOS2SuperscriptXSize=None, openTypeOS2SuperscriptYSize=None,
    openTypeOS2SuperscriptXOffset=None, openTypeOS2SuperscriptYOffset=None,
    openTypeOS2StrikeoutSize=None, openTypeOS2StrikeoutPosition=None,
    openTypeVheaVertTypoAscender=None, openTypeVheaVertTypoDescender=None,
    openTypeVheaVertTypoLineGap=None, openTypeVheaCaretSlopeRise=0,
    openTypeVheaCaretSlopeRun=1, openTypeVheaCaretOffset=0, postscriptUniqueID=None,
    postscriptWeightName=None, postscriptIsFixedPitch=False, postscriptBlueValues=[],
    postscriptOtherBlues=[], postscriptFamilyBlues=[], postscriptFamilyOtherBlues=[],
    postscriptStemSnapH=[], postscriptStemSnapV=[], postscriptBlueFuzz=0,
    postscriptBlueShift=7, postscriptForceBold=0, postscriptDefaultWidthX=200,
    postscriptNominalWidthX=0, postscriptDefaultCharacter=None,
    postscriptWindowsCharacterSet=None, macintoshFONDFamilyID=None, macintoshFONDName=None)

_SPECIAL = dict(
    ascender=lambda i: _ot_round(_upm(i) * 0.8),
    descender=lambda i: -_ot_round(_upm(i) * 0.2),
    capHeight=lambda i: _ot_round(_upm(i) * 0.7),
    xHeight=lambda i: _ot_round(_upm(i) * 0.5),
    styleMapFamilyName=_style_map_family,
    styleMapStyleName=_style_map_style,
    openTypeHeadCreated=_created,
    openTypeHheaAscender=lambda i: info_value(i, "ascender")
    + info_value(i, "openTypeOS2TypoLineGap"),
    openTypeHheaDescender=lambda i: info_value(i, "descender"),
    openTypeHheaCaretSlopeRise=_slope_rise,
    openTypeHheaCaretSlopeRun=_slope_run,
    openTypeNameVersion=_name_version,
    openTypeNameUniqueID=_unique_id,
    openTypeNamePreferredFamilyName=lambda i: info_value(i, "familyName"),
    openTypeNamePreferredSubfamilyName=lambda i: info_value(i, "styleName"),
    openTypeNameWWSFamilyName=lambda i: None,
    openTypeNameWWSSubfamilyName=lambda i: None,
    openTypeOS2TypoAscender=lambda i: info_value(i, "ascender"),
    openTypeOS2TypoDescender=lambda i: info_value(i, "descender"),
    openTypeOS2TypoLineGap=_typo_line_gap,
    openTypeOS2WinAscent=lambda i: info_value(i, "ascender")
    + info_value(i, "openTypeOS2TypoLineGap"),
    openTypeOS2WinDescent=lambda i: abs(info_value(i, "descender")),
    postscriptFontName=_ps_font_name,
    postscriptFullName=lambda i: "%s %s" % (
        info_value(i, "openTypeNamePreferredFamilyName"),
        info_value(i, "openTypeNamePreferredSubfamilyName")),
    postscriptSlantAngle=lambda i: info_value(i, "italicAngle"),
    postscriptUnderlineThickness=lambda i: _upm(i) * 0.05,
    postscriptUnderlinePosition=lambda i: _upm(i) * -0.075,
    postscriptBlueScale=_blue_scale)


def info_value(info, attr):
    """The font info's ``attr``, or where it is unset (None) the value ufo2ft
    compiles in its place (its ``getAttrWithFallback``: the same static values and
    derived ones)."""
    value = getattr(info, attr, None)
    if value is not None:
        return value
    if attr in _SPECIAL:
        return _SPECIAL[attr](info)
    return _STATIC[attr]


def _int_list_to_num(values, start, length):
    """ufo2ft's ``intListToNum``: the bits ``values`` (in [start, start + length))
    as an integer."""
    return sum(1 << (i - start) for i in set(values) if start <= i < start + length)


def _time_value(date):
    """Seconds since 1970 of a UFO date (``YYYY/MM/DD HH:MM:SS``, UTC) as ufo2ft
    reads it with ``time.strptime``, 0 where that fails.  A date of exactly that
    form in ASCII digits (what :func:`_date_now` writes) is read field by field, with
    strptime's ranges and calendar: its ``_strptime`` module builds the locale's
    tables and patterns as it loads (~10 M instructions of every ``morph stroke``)."""
    import calendar

    digits = date[:4] + date[5:7] + date[8:10] + date[11:13] + date[14:16] + date[17:] \
        if isinstance(date, str) and len(date) == 19 else ""
    if digits.isdigit() and digits.isascii() \
            and (date[4], date[7], date[10], date[13], date[16]) == ("/", "/", " ", ":", ":"):
        y, mo, d, h, mi, sec = (int(digits[i:j]) for i, j in
                                ((0, 4), (4, 6), (6, 8), (8, 10), (10, 12), (12, 14)))
        if y >= 1 and 1 <= mo <= 12 and 1 <= d <= calendar.monthrange(y, mo)[1] \
                and h <= 23 and mi <= 59 and sec <= 61:
            return calendar.timegm((y, mo, d, h, mi, sec))
        return 0
    try:
        return calendar.timegm(time.strptime(date, _DATE_FORMAT))
    except ValueError:
        return 0


def full_name(info):
    """The full name ufo2ft writes (name ID 4): the typographic family and
    subfamily."""
    return ("%s %s" % (info_value(info, "openTypeNamePreferredFamilyName"),
                       info_value(info, "openTypeNamePreferredSubfamilyName"))).strip()

"""Raster output: anti-aliased PNG of regions, GIF and APNG animations (Pillow).

Filling is a nonzero-winding scanline rasteriser written with numpy: loops are
flattened to polylines within 0.1 supersampled pixel, every polyline edge adds its
direction (+1 down, -1 up) at the first pixel centre right of where it crosses each
pixel-centre row, and a cumulative sum along the row gives each pixel centre's winding
number.  Coverage is sampled at ``supersample**2`` centres per output pixel and
averaged (box filter), which anti-aliases the edges.  Holes are holes because the
winding rule sees the clockwise hole loops.  Strokes are drawn with
``PIL.ImageDraw.line`` on the supersampled mask.
"""

import math

import numpy as np

from .. import polyline as pl
from ..fonts.deferred import pillow
from ..region import polyline_edges
from . import frame_bbox, normalize_shapes

Image, ImageColor = pillow("Image", "ImageColor")

#: coverage samples per image, at most (supersample lowered to fit): 2^28
MAX_SAMPLES = 1 << 28

__all__ = ["render_png", "render_palette", "render_palettes", "write_png", "frames_to_gif", "save_animation", "coverage_mask",
           "coverage_counts", "exact_palette", "gif_frame"]


def _rgba(color, opacity=1.0):
    if color is None or (isinstance(color, str) and color.strip().lower() == "none"):
        return None  # SVG's "none": no paint
    if isinstance(color, str):
        c = ImageColor.getrgb(color)
    else:
        c = tuple(int(v) for v in color)
    if len(c) == 3:
        c = c + (255,)
    return c[:3] + (int(round(c[3] * opacity)),)


def _row_crossings(polylines, height, width):
    """Where the edges of closed ``polylines`` (pixel coordinates, see
    :func:`coverage_mask`) cross the rows of pixel centres: (rows, cols, directions),
    one entry per crossing of a row j (lo <= j + 0.5 < hi); the crossing adds its
    direction (+1 down, -1 up) from column ``cols`` on, the first pixel centre at or
    right of it (clipped to [0, width]: a crossing right of the image is kept, so
    every row's directions still add up to 0)."""
    a, b = polyline_edges(polylines)
    empty = np.zeros(0, np.int64)
    if not len(a):
        return empty, empty, empty
    x0, y0, x1, y1 = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    moving = y0 != y1
    x0, y0, x1, y1 = x0[moving], y0[moving], x1[moving], y1[moving]
    direction = np.where(y1 > y0, 1, -1)
    lo, hi = np.minimum(y0, y1), np.maximum(y0, y1)
    # rows j with lo <= j + 0.5 < hi
    first = np.clip(np.ceil(lo - 0.5), 0, height).astype(np.int64)
    stop = np.clip(np.ceil(hi - 0.5), 0, height).astype(np.int64)
    counts = np.maximum(stop - first, 0)
    total = int(counts.sum())
    if not total:
        return empty, empty, empty
    edge = np.repeat(np.arange(len(counts)), counts)
    offsets = np.cumsum(counts) - counts
    rows = first[edge] + (np.arange(total) - offsets[edge])
    yc = rows + 0.5
    t = (yc - y0[edge]) / (y1[edge] - y0[edge])
    xc = x0[edge] + t * (x1[edge] - x0[edge])
    cols = np.clip(np.ceil(xc - 0.5), 0, width).astype(np.int64)
    return rows, cols, direction[edge]


def coverage_mask(polylines, height, width):
    """Boolean (height, width) mask of pixel centres with nonzero winding number.

    ``polylines`` are closed (k, 2) arrays in pixel coordinates (x right, y down,
    pixel (i, j) covering [i, i+1) x [j, j+1), centre (i + 0.5, j + 0.5)).
    """
    rows, cols, direction = _row_crossings(polylines, height, width)
    acc = np.zeros((height, width + 1), np.int16 if len(rows) < 30000 else np.int32)
    np.add.at(acc, (rows, cols), direction.astype(acc.dtype))
    return np.cumsum(acc[:, :width], axis=1, dtype=acc.dtype) != 0


def coverage_counts(polylines, height, width, k):
    """For each pixel of a (height, width) image, how many of its k x k sample
    centres have a nonzero winding number: ``_box_sum(coverage_mask(polylines,
    height * k, width * k), k)`` exactly, ``polylines`` in sample coordinates.

    Not sample by sample: each sample row's crossings, sorted, give the runs of
    samples between two crossings with a nonzero winding after the first (a row's
    directions add up to 0, so one running sum serves every row).  A run [u, v) of
    samples adds k per pixel from pixel u // k on, less u % k in that pixel, and takes
    the same off from v: as steps of a running sum along the output row, k - u % k
    at pixel u // k and u % k at the next, -(k - v % k) at v // k and -(v % k) at
    the next.  The steps are gathered in one count per pixel of (height, width + 2)
    (the next pixel of the last column stays in its row) and one cumulative sum
    in int32 turns them into the counts, (height, width) uint16."""
    big_h, big_w = height * k, width * k
    rows, cols, direction = _row_crossings(polylines, big_h, big_w)
    if len(rows) < 2:
        return np.zeros((height, width), np.uint16)
    order = np.lexsort((cols, rows))
    rows, cols = rows[order], cols[order]
    winding = np.cumsum(direction[order])
    run = np.flatnonzero(winding[:-1] != 0)  # [cols[i], cols[i + 1]) is covered
    u, v = cols[run], cols[run + 1]
    at_u = (rows[run] // k) * (width + 2) + u // k
    at_v = (rows[run] // k) * (width + 2) + v // k
    ru, rv = u % k, v % k
    steps = np.bincount(np.concatenate([at_u, at_u + 1, at_v, at_v + 1]),
                        np.concatenate([k - ru, ru, rv - k, -rv]), height * (width + 2))
    # int32 (a count is at most k^2): numpy's float64 cumsum along rows is 7 times slower
    out = np.cumsum(steps.reshape(height, width + 2).astype(np.int32), axis=1, dtype=np.int32)
    return out[:, :width].astype(np.uint16)


def _fit(size, frame):
    """(width, height, scale, frame) for an output size; the frame is centred."""
    x0, y0, x1, y1 = frame
    w, h = x1 - x0, y1 - y0
    if np.isscalar(size):
        side = max(w, h)
        scale = size / side
        width, height = max(1, int(round(w * scale))), max(1, int(round(h * scale)))
    else:
        width, height = int(size[0]), int(size[1])
        scale = min(width / w, height / h)
    cx, cy = 0.5 * (x0 + x1), 0.5 * (y0 + y1)
    return width, height, scale, (cx, cy)


def _raster(items, size, margin, bbox, supersample):
    """(width, height, k, to_px, flat_tol) of a render: the frame (``bbox`` or the
    shapes' union box, grown by ``margin``) fitted to ``size`` and centred, ``k``
    samples per pixel along each axis (lowered to at most MAX_SAMPLES samples),
    ``to_px`` the map of region points to sample coordinates and ``flat_tol`` the
    flattening of 0.1 sample in region units."""
    frame = frame_bbox(items, bbox, margin)
    width, height, scale, (cx, cy) = _fit(size, frame)
    k = int(supersample)
    if k < 1:
        raise ValueError("supersample must be >= 1, got %r" % (supersample,))
    # at most MAX_SAMPLES coverage samples (4 at 512 and 4096 px, 2 at 8192 px): the
    # sample mask and its winding sums stay within a few GB at the largest sizes
    k = max(1, min(k, int(math.sqrt(MAX_SAMPLES / (width * height)))))
    big_w, big_h, s = width * k, height * k, scale * k

    def to_px(points):
        return np.column_stack([(points[:, 0] - cx) * s + big_w / 2.0,
                                (cy - points[:, 1]) * s + big_h / 2.0])

    return width, height, k, to_px, 0.1 / s


def _fill_counts(loops, width, height, k, to_px, flat_tol):
    """Covered samples of each pixel (:func:`coverage_counts`) of a region's fill."""
    polys = [to_px(pl.flatten_loop(loop, flat_tol)) for loop in loops if loop]
    return polys, coverage_counts(polys, height, width, k)


def _alpha(hits, color, k):
    """The box filter: the share of covered samples times the colour's alpha,
    rounded to 0-255 (uint8)."""
    return ((hits.astype(np.uint32) * (2 * color[3]) + k * k) // (2 * k * k)).astype(np.uint8)


def _layer(color, alpha):
    """An RGBA image of ``color`` with the alpha channel ``alpha`` (2-d uint8)."""
    layer = Image.new("RGBA", (alpha.shape[1], alpha.shape[0]), color[:3] + (0,))
    layer.putalpha(Image.fromarray(alpha, "L"))
    return layer


def render_png(shapes, size=512, margin=0.05, fill="black", stroke=None, stroke_width=1.0,
               background="white", bbox=None, supersample=4):
    """Anti-aliased image of shapes (see :mod:`morph.render` for the shapes forms).

    ``size``: the longer side in pixels (int) or ``(width, height)``; the frame
    (``bbox`` or the shapes' union box, grown by ``margin`` times its larger side) is
    fitted and centred, aspect preserved.  Pass the same ``bbox`` for every frame of an
    animation.  ``fill``/``stroke``/``background``: Pillow colours (``stroke`` None:
    no outline; ``background`` None: transparent).  ``stroke_width`` in output pixels.
    ``supersample``: samples per pixel along each axis.  Returns an RGBA image when the
    background is None, else RGB.
    """
    items = normalize_shapes(shapes)
    width, height, k, to_px, flat_tol = _raster(items, size, margin, bbox, supersample)
    bg = _rgba(background) if background is not None else (0, 0, 0, 0)
    canvas = Image.new("RGBA", (width, height), bg)
    for loops, style in items:
        opacity = style.get("opacity", 1.0)
        f = _rgba(style.get("fill", fill), opacity)
        layers = []
        if f is not None:
            polys, hits = _fill_counts(loops, width, height, k, to_px, flat_tol)
            layers.append((f, hits))
        else:
            polys = [to_px(pl.flatten_loop(loop, flat_tol)) for loop in loops if loop]
        st = _rgba(style.get("stroke", stroke), opacity)
        if st is not None:
            from PIL import ImageDraw  # strokes only: it imports ImageFont

            img = Image.new("L", (width * k, height * k), 0)
            draw = ImageDraw.Draw(img)
            lw = max(1, int(round(style.get("stroke_width", stroke_width) * k)))
            for p in polys:
                pts = [tuple(v) for v in (p - 0.5)] + [tuple(p[0] - 0.5)]
                draw.line(pts, fill=255, width=lw, joint="curve")
            layers.append((st, _box_sum((np.asarray(img) > 127).view(np.uint8), k)))
        for color, hits in layers:
            # "over" compositing with straight alpha (Pillow)
            canvas.alpha_composite(_layer(color, _alpha(hits, color, k)))
    return canvas if background is None else canvas.convert("RGB")


def render_palette(region, size=512, margin=0.05, fill="black", background="white",
                   bbox=None, supersample=4):
    """:func:`render_png` of one filled region on an opaque background as a palette
    image ("P"), the same RGB pixels in a byte each: a pixel's index is how many of
    its k x k samples are covered (0 ... k^2; past 256 levels, the alpha they give,
    0 ... 255) and the palette holds the colour render_png composes for it, made by
    the same Pillow compositing on a row of those levels.  No canvas is composited
    and converted, and no colours are collected (:func:`exact_palette`): what a
    frame's PNG and GIF frame are."""
    items = normalize_shapes(region)
    if len(items) != 1 or items[0][1]:
        raise ValueError("render_palette draws one region, without a style")
    return render_palettes([items[0][0]], size, margin, fill, background, bbox,
                           supersample)[0]


def render_palettes(regions, size=512, margin=0.05, fill="black", background="white",
                    bbox=None, supersample=4):
    """:func:`render_palette` of each of ``regions`` (lists of loops), all in one
    frame (``bbox``, else the union of their boxes, grown by ``margin``), their
    loops flattened in one batch: the frames of an animation."""
    bg, f = _rgba(background), _rgba(fill)
    if bg is None or bg[3] != 255:
        raise ValueError("render_palette needs an opaque background, got %r" % (background,))
    regions = [[loop for loop in r if loop] for r in regions]
    if bbox is None:
        bbox = frame_bbox([r for r in regions if r], margin=0.0)
    width, height, k, to_px, flat_tol = _raster(None, size, margin, bbox, supersample)
    if f is None:
        alpha, index = np.zeros(1, np.uint8), [np.zeros((height, width), np.uint8)] * len(regions)
    else:
        polys = iter(pl.flatten_loops([loop for r in regions for loop in r], flat_tol))
        hits = [coverage_counts([to_px(next(polys)) for _ in r], height, width, k)
                for r in regions]
        if k * k < 256:
            alpha, index = _alpha(np.arange(k * k + 1), f, k), [h.astype(np.uint8) for h in hits]
        else:
            alpha, index = np.arange(256, dtype=np.uint8), [_alpha(h, f, k) for h in hits]
    palette = Image.new("RGBA", (len(alpha), 1), bg)
    if f is not None:
        palette.alpha_composite(_layer(f, alpha[None]))
    palette = palette.convert("RGB").tobytes()
    images = []
    for ix in index:
        image = Image.fromarray(ix, "L")
        image.putpalette(palette)
        images.append(image)
    return images


def _box_sum(mask, k):
    """Sums of k x k blocks of a 0/1 uint8 mask (strided adds: an order of magnitude
    faster than a reduction over reshaped axes)."""
    rows = mask[0::k].astype(np.uint16)
    for i in range(1, k):
        rows += mask[i::k]
    out = rows[:, 0::k].copy()
    for j in range(1, k):
        out += rows[:, j::k]
    return out


def write_png(path, shapes, **kwargs):
    """Write :func:`render_png` ``(shapes, **kwargs)`` to ``path``; returns the image."""
    image = render_png(shapes, **kwargs)
    image.save(path, format="PNG")
    return image


def _flatten_rgb(image):
    if image.mode == "RGBA":
        base = Image.new("RGB", image.size, "white")
        base.paste(image, mask=image.split()[3])
        return base
    return image.convert("RGB")


def exact_palette(image):
    """An RGB image of at most 256 colours (one fill anti-aliased on a background
    has supersample**2 + 1) as a palette image of its own colours: the same pixels
    in a byte each, which a PNG stores in a third of the time and space of RGB;
    None for an image of more colours (or not RGB).  Each pixel's index is found
    by its colour in the sorted table of the image's colours (Pillow's quantize to
    a given palette is not exact: it moved greys by up to 3 levels)."""
    colors = image.getcolors(256) if image.mode == "RGB" else None
    if colors is None:
        return None
    rgb = np.asarray(image).astype(np.uint32)
    key = (rgb[..., 0] << 16) | (rgb[..., 1] << 8) | rgb[..., 2]
    table = np.array(sorted((r << 16) | (g << 8) | b for _, (r, g, b) in colors), np.uint32)
    out = Image.fromarray(np.searchsorted(table, key).astype(np.uint8), "L")
    out.putpalette(np.stack([table >> 16, (table >> 8) & 255, table & 255], axis=1)
                   .astype(np.uint8).tobytes())
    return out


def gif_frame(image):
    """An image as a GIF frame: composited on white; an image of at most 256 colours
    keeps them exactly, in a palette of its own colours (:func:`exact_palette`);
    others get an adaptive 256-colour palette (median cut)."""
    rgb = _flatten_rgb(image)
    frame = exact_palette(rgb)
    return rgb.convert("P", palette=Image.Palette.ADAPTIVE) if frame is None else frame


def frames_to_gif(images, path, duration=50, loop=0):
    """Write an animated GIF: ``duration`` ms per frame, ``loop`` 0 = forever.

    Transparent pixels are composited on white (GIF has 1-bit transparency); each
    frame is quantised to an adaptive 256-colour palette (:func:`gif_frame`; images
    in palette mode are taken as they are).
    """
    frames = [im if im.mode == "P" else gif_frame(im) for im in images]
    if not frames:
        raise ValueError("no frames to write")
    # a .gif path names the format: Pillow then loads the GIF plugin alone (with
    # format= it loads five, JPEG's among them: ~10 ms of every frame command)
    named = str(path).lower().endswith(".gif")
    frames[0].save(path, format=None if named else "GIF", save_all=True,
                   append_images=frames[1:], duration=duration, loop=loop, disposal=2)
    return path


def save_animation(images, path, duration=50, loop=0):
    """Animation by suffix: ``.gif`` (GIF) or ``.apng`` / ``.png`` (APNG, full colour
    and alpha)."""
    path = str(path)
    images = list(images)
    if not images:
        raise ValueError("no frames to write")
    if path.lower().endswith(".gif"):
        return frames_to_gif(images, path, duration, loop)
    if path.lower().endswith((".apng", ".png")):
        images[0].save(path, format="PNG", save_all=True, append_images=images[1:],
                       duration=duration, loop=loop)
        return path
    raise ValueError("animation format from suffix: .gif, .apng or .png, got %r" % path)

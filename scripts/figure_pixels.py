#!/usr/bin/env python3
"""Pixel checks of a beamflow figure, standard library only (CI's python3 has no numpy).

  figure_pixels.py size PNG
      Prints the PNG's width and height (the browser window the SVG is shot in).

  figure_pixels.py same BROWSER.png BEAMFLOW.png
      The browser's screenshot of a figure's SVG and beamflow's PNG of that figure put
      their text and lines in the same places: of the dark pixels (luminance < DARK) of
      each image, at least MATCHED lie within NEAR px of a dark pixel of the other.
      Exact equality is not asked: the two rasterisers anti-alias edges differently.

  figure_pixels.py antialiased BEAMFLOW.png
      Plotted lines have anti-aliased edges: of the pixels of the most common saturated
      colour (a plotted series) and its blends with white, at least BLENDED are blends
      with a coverage strictly between 15 % and 85 %. A renderer without anti-aliasing
      draws each pixel in the full colour or not at all, so it has none.

  figure_pixels.py self-test BROWSER.png BEAMFLOW.png
      Both checks fail on spoiled copies: the PNG shifted by SHIFT px, and the PNG with
      every blend snapped to full colour or white (as an aliased renderer draws it).

Exit status 1 with the measured numbers when a check fails.
"""

import struct
import sys
import zlib

DARK = 128  # luminance below which a pixel is ink (text, axes, lines)
NEAR = 1  # px: tolerance for the rasterisers' different edge placement
MATCHED = 0.97  # fraction of each image's ink that must lie near the other's
BLENDED = 0.15  # fraction of a series' pixels that must be partial-coverage blends
SHIFT = 2  # px: the self-test's displacement, less than a glyph stroke's width


class Image:
    """An 8-bit RGB image as rows of (r, g, b) tuples."""

    def __init__(self, width, height, rows):
        self.width, self.height, self.rows = width, height, rows

    def luminance(self):
        return [[(299 * r + 587 * g + 114 * b) // 1000 for r, g, b in row] for row in self.rows]


def read_png(path):
    """Decode an 8-bit, non-interlaced RGB or RGBA PNG (what Chromium and resvg write);
    alpha is composited on white, the figures' background."""
    with open(path, "rb") as f:
        data = f.read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        sys.exit(f"figure_pixels: {path} is not a PNG")
    pos, idat, header = 8, [], None
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        pos += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace:
        sys.exit(f"figure_pixels: {path}: only 8-bit non-interlaced RGB/RGBA is read")
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(b"".join(idat))
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        start = y * (stride + 1)
        line = unfilter(raw[start], bytearray(raw[start + 1 : start + 1 + stride]), previous, channels)
        rows.append(to_rgb(line, channels))
        previous = line
    return Image(width, height, rows)


def unfilter(kind, line, previous, bpp):
    """Undo one scanline's PNG filter (RFC 2083, section 6)."""
    if kind == 1:
        for i in range(bpp, len(line)):
            line[i] = (line[i] + line[i - bpp]) & 255
    elif kind == 2:
        for i in range(len(line)):
            line[i] = (line[i] + previous[i]) & 255
    elif kind == 3:
        for i in range(len(line)):
            left = line[i - bpp] if i >= bpp else 0
            line[i] = (line[i] + (left + previous[i]) // 2) & 255
    elif kind == 4:
        for i in range(len(line)):
            a = line[i - bpp] if i >= bpp else 0
            b = previous[i]
            c = previous[i - bpp] if i >= bpp else 0
            p = a + b - c
            pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
            predictor = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            line[i] = (line[i] + predictor) & 255
    return line


def to_rgb(line, channels):
    if channels == 3:
        return [tuple(line[i : i + 3]) for i in range(0, len(line), 3)]
    out = []
    for i in range(0, len(line), 4):
        a = line[i + 3]
        out.append(tuple((line[i + k] * a + 255 * (255 - a)) // 255 for k in range(3)))
    return out


# --- text and lines in the same places -----------------------------------------------


def ink(image):
    return {(x, y) for y, row in enumerate(image.luminance()) for x, v in enumerate(row) if v < DARK}


def near_fraction(ink_a, ink_b):
    """Fraction of ink_a's pixels within NEAR px (Chebyshev) of a pixel of ink_b."""
    offsets = [(dx, dy) for dx in range(-NEAR, NEAR + 1) for dy in range(-NEAR, NEAR + 1)]
    hit = sum(1 for x, y in ink_a if any((x + dx, y + dy) in ink_b for dx, dy in offsets))
    return hit / max(len(ink_a), 1)


def same_places(browser, beamflow):
    """(passed, message) for the browser's screenshot against beamflow's PNG."""
    if (browser.width, browser.height) != (beamflow.width, beamflow.height):
        return False, (
            f"sizes differ: browser {browser.width}x{browser.height}, "
            f"beamflow {beamflow.width}x{beamflow.height}"
        )
    a, b = ink(browser), ink(beamflow)
    ab, ba = near_fraction(a, b), near_fraction(b, a)
    ok = min(ab, ba) >= MATCHED and a and b
    return ok, (
        f"{ab:.1%} of the browser's {len(a)} ink pixels and {ba:.1%} of beamflow's {len(b)} "
        f"lie within {NEAR} px of the other's (at least {MATCHED:.0%} asked)"
    )


# --- anti-aliased line edges ------------------------------------------------------------


def saturated(rgb):
    return max(rgb) - min(rgb) > 60


def coverage(rgb, colour):
    """The coverage a with rgb = a*colour + (1-a)*white, or None when rgb is no such blend."""
    spans = [(255 - c, 255 - v) for c, v in zip(colour, rgb)]
    widest = max(spans, key=lambda s: s[0])
    if widest[0] == 0:
        return None
    a = widest[1] / widest[0]
    if not 0.0 < a <= 1.0:
        return None
    return a if all(abs(s[0] * a - s[1]) <= 12 for s in spans) else None


def series_colour(image):
    counts = {}
    for row in image.rows:
        for rgb in row:
            if saturated(rgb):
                counts[rgb] = counts.get(rgb, 0) + 1
    return max(counts, key=counts.get) if counts else None


def antialiased(image):
    colour = series_colour(image)
    if colour is None:
        return False, "no saturated colour: no plotted series found"
    full = partial = 0
    for row in image.rows:
        for rgb in row:
            if rgb == (255, 255, 255):
                continue
            a = coverage(rgb, colour)
            if a is None:
                continue
            if a >= 0.85:
                full += 1
            elif a > 0.15:
                partial += 1
    fraction = partial / max(full + partial, 1)
    return fraction >= BLENDED, (
        f"series colour #{colour[0]:02x}{colour[1]:02x}{colour[2]:02x}: {partial} partial-coverage "
        f"edge pixels beside {full} full ones ({fraction:.1%}; at least {BLENDED:.0%} asked)"
    )


# --- spoiled copies for the self-test --------------------------------------------------


def shifted(image, dx, dy):
    white = (255, 255, 255)
    rows = []
    for y in range(image.height):
        sy = y - dy
        src = image.rows[sy] if 0 <= sy < image.height else [white] * image.width
        rows.append([src[x - dx] if 0 <= x - dx < image.width else white for x in range(image.width)])
    return Image(image.width, image.height, rows)


def aliased(image):
    """Every pixel of a blend snapped to its full colour or to white."""
    colour = series_colour(image)
    rows = []
    for row in image.rows:
        out = []
        for rgb in row:
            a = coverage(rgb, colour) if rgb != (255, 255, 255) else None
            out.append(rgb if a is None else (colour if a >= 0.5 else (255, 255, 255)))
        rows.append(out)
    return Image(image.width, image.height, rows)


def report(name, result):
    ok, message = result
    print(f"figure_pixels: {name}: {'ok' if ok else 'FAILED'}: {message}")
    return ok


def main(argv):
    if len(argv) == 3 and argv[1] == "size":
        with open(argv[2], "rb") as f:
            print(*struct.unpack(">II", f.read(24)[16:24]))
        return 0
    if len(argv) == 4 and argv[1] == "same":
        ok = report("same places", same_places(read_png(argv[2]), read_png(argv[3])))
    elif len(argv) == 3 and argv[1] == "antialiased":
        ok = report("anti-aliased", antialiased(read_png(argv[2])))
    elif len(argv) == 4 and argv[1] == "self-test":
        browser, beamflow = read_png(argv[2]), read_png(argv[3])
        moved = same_places(browser, shifted(beamflow, SHIFT, SHIFT))
        stepped = antialiased(aliased(beamflow))
        ok = not moved[0] and not stepped[0]
        print(
            f"figure_pixels: self-test: {'ok' if ok else 'FAILED'}: shifted by {SHIFT} px: "
            f"{moved[1]}; snapped to full colour: {stepped[1]} (both must fail)"
        )
    else:
        sys.exit(__doc__)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv))

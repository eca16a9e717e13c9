#!/usr/bin/env python3
"""Side-by-side previews of crackle texture sets for docs/user-guide.md.

Usage:
  lit_preview.py OUT.jpg [--panel PX] [--crop FX,FY,FW,FH] [--quality Q]
                 LABEL=DIR/NAME [LABEL=DIR/NAME ...]

Each DIR/NAME is a baked texture set (DIR/NAME_Color.png, _NormalGL.png,
_AmbientOcclusion.png). Every set becomes one column: its label on top, the lit relief
(albedo x Lambert of the OpenGL normal map, light from the upper left, x ambient occlusion)
and below it the colour map as baked. --crop takes a window of each map in fractions of its
width and height (default: the whole map); --panel is the width of one panel in pixels.
Needs Pillow and NumPy (Debian: python3-pil python3-numpy).
"""
import sys

import numpy as np
from PIL import Image, ImageDraw, ImageFont

# Light from the upper left at 45 degrees elevation, in tangent space (x right, y up = +v,
# the OpenGL convention of _NormalGL: green up).
LIGHT = np.array([-0.5, 0.5, 0.7071])
LIGHT = LIGHT / np.linalg.norm(LIGHT)


def srgb_to_linear(c):
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def linear_to_srgb(c):
    c = np.clip(c, 0.0, 1.0)
    return np.where(c <= 0.0031308, c * 12.92, 1.055 * c ** (1 / 2.4) - 0.055)


def load(path, crop):
    im = Image.open(path)
    if crop:
        w, h = im.size
        fx, fy, fw, fh = crop
        im = im.crop((round(fx * w), round(fy * h), round((fx + fw) * w), round((fy + fh) * h)))
    return im


def lit_relief(prefix, crop):
    albedo = np.asarray(load(prefix + "_Color.png", crop).convert("RGB"), np.float64) / 255.0
    normal = np.asarray(load(prefix + "_NormalGL.png", crop).convert("RGB"), np.float64) / 255.0
    ao = np.asarray(load(prefix + "_AmbientOcclusion.png", crop).convert("L"), np.float64) / 255.0
    n = normal * 2.0 - 1.0
    n /= np.maximum(np.linalg.norm(n, axis=2, keepdims=True), 1e-6)
    # Lambert, scaled so a flat surface keeps its albedo (slopes facing the light get brighter).
    lambert = np.clip(n @ LIGHT, 0.0, None) / LIGHT[2]
    lit = srgb_to_linear(albedo) * lambert[..., None] * ao[..., None]
    return Image.fromarray((linear_to_srgb(lit) * 255.0 + 0.5).astype(np.uint8))


def font(size):
    for path in ("/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                 "/usr/share/fonts/TTF/DejaVuSans.ttf"):
        try:
            return ImageFont.truetype(path, size)
        except OSError:
            pass
    return ImageFont.load_default()


def main(argv):
    panel, crop, quality, out, sets = 240, None, 85, None, []
    i = 0
    while i < len(argv):
        a = argv[i]
        if a == "--panel":
            panel = int(argv[i + 1]); i += 2; continue
        if a == "--crop":
            crop = [float(x) for x in argv[i + 1].split(",")]; i += 2; continue
        if a == "--quality":
            quality = int(argv[i + 1]); i += 2; continue
        if out is None:
            out = a
        else:
            label, _, prefix = a.rpartition("=")
            sets.append((label, prefix))
        i += 1
    if out is None or not sets:
        sys.exit(__doc__)
    if panel > 320:
        sys.exit("lit_preview.py: --panel is at most 320 px (the guide's image budget)")

    columns = []
    for label, prefix in sets:
        lit = lit_relief(prefix, crop)
        color = load(prefix + "_Color.png", crop).convert("RGB")
        h = round(panel * lit.size[1] / lit.size[0])
        columns.append((label, lit.resize((panel, h), Image.LANCZOS),
                        color.resize((panel, h), Image.LANCZOS)))

    gap, label_h = 4, 22
    f = font(13)
    h = columns[0][1].size[1]
    sheet = Image.new("RGB", (len(columns) * panel + (len(columns) - 1) * gap,
                              label_h + 2 * h + gap), "white")
    draw = ImageDraw.Draw(sheet)
    for k, (label, lit, color) in enumerate(columns):
        x = k * (panel + gap)
        draw.text((x + 3, 4), label, fill=(20, 20, 20), font=f)
        sheet.paste(lit, (x, label_h))
        sheet.paste(color, (x, label_h + h + gap))
    sheet.save(out, "JPEG", quality=quality, optimize=True, progressive=True)


if __name__ == "__main__":
    main(sys.argv[1:])

"""Previews and the contact sheet of samples/ from baked texture sets (called by scripts/gallery).

usage: gallery.py WORK OUT
WORK holds commands.tsv (preset, folder, command, seconds) and, per preset, the folder of maps
and <folder>.json (the bake report). OUT receives <folder>.jpg (colour beside a lit render of
the relief, 256 px each), contact-sheet.jpg and README.md. Presets already in OUT's README.md
that WORK does not hold keep their row and preview, so `scripts/gallery mud` refreshes mud alone.
"""
import json
import os
import re
import sys

from PIL import Image, ImageDraw

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from lit_preview import font, lit_relief  # noqa: E402  (the guide's lit render and font: one definition)

PANEL = 256


def panel(image):
    w, h = image.size
    return image.resize((PANEL, max(1, round(PANEL * h / w))), Image.LANCZOS)


ROW = re.compile(r"^\| `([^`]+)` \| !\[[^]]*\]\(([^)]+)\.jpg\) \| `([^`]+)` \| (\d+) s \|$")


def kept_entries(out, rebaked):
    """The rows of OUT's README.md for presets not baked now: preset -> (folder, command, seconds)."""
    readme = os.path.join(out, "README.md")
    kept = {}
    if os.path.exists(readme):
        for line in open(readme):
            m = ROW.match(line.rstrip("\n"))
            if m and m.group(1) not in rebaked and os.path.exists(os.path.join(out, m.group(2) + ".jpg")):
                kept[m.group(1)] = (m.group(2), m.group(3), m.group(4))
    return kept


def main(work, out):
    os.makedirs(out, exist_ok=True)
    rows = [line.rstrip("\n").split("\t") for line in open(os.path.join(work, "commands.tsv")) if line.strip()]
    label_font = font(13)
    entries = kept_entries(out, {row[0] for row in rows})
    for preset, folder, command, seconds in rows:
        maps = os.path.join(work, folder)
        name = next(f[: -len("_Color.png")] for f in os.listdir(maps) if f.endswith("_Color.png"))
        report = json.load(open(os.path.join(work, folder + ".json")))
        seed = report.get("seed", "?")
        color = panel(Image.open(f"{maps}/{name}_Color.png").convert("RGB"))
        lit = panel(lit_relief(f"{maps}/{name}", None))
        preview = Image.new("RGB", (2 * PANEL, max(color.size[1], PANEL // 2)), "white")
        preview.paste(color, (0, 0))
        preview.paste(lit, (PANEL, 0))
        preview.save(os.path.join(out, folder + ".jpg"), quality=85)
        entries[preset] = (folder, f"{command} --seed {seed}", seconds)
    tiles, table = [], []
    for preset in sorted(entries):
        folder, command, seconds = entries[preset]
        tiles.append((preset, command, Image.open(os.path.join(out, folder + ".jpg")).convert("RGB")))
        table.append(f"| `{preset}` | ![{preset}]({folder}.jpg) | `{command}` | {seconds} s |")
    columns = 3
    label = 32
    cell_h = max(t[2].size[1] for t in tiles) + label
    sheet = Image.new("RGB", (columns * 2 * PANEL, ((len(tiles) + columns - 1) // columns) * cell_h), "white")
    draw = ImageDraw.Draw(sheet)
    for k, (preset, command, preview) in enumerate(tiles):
        x, y = (k % columns) * 2 * PANEL, (k // columns) * cell_h
        sheet.paste(preview, (x, y + label))
        draw.text((x + 4, y + 2), preset, fill="black", font=label_font)
        draw.text((x + 4, y + 15), command, fill=(90, 90, 90), font=label_font)
    sheet.save(os.path.join(out, "contact-sheet.jpg"), quality=82)
    with open(os.path.join(out, "README.md"), "w") as f:
        f.write("# Samples\n\nEvery built-in preset baked at 512 px with its own seed: the colour map beside a "
                "lit render of its relief (normal map lit from the upper left, times the occlusion map). "
                "Regenerate with `scripts/gallery` (about 15 minutes; not part of the tests).\n\n"
                "![contact sheet](contact-sheet.jpg)\n\n| preset | preview | command | bake time |\n|---|---|---|---|\n")
        f.write("\n".join(table) + "\n")
        crops = sorted(c for c in os.listdir(os.path.join(out, "crops")) if c.endswith("-2048.jpg")) \
            if os.path.isdir(os.path.join(out, "crops")) else []
        if crops:
            f.write("\n## Full resolution\n\nA 512-px square from the middle of the tile baked at 2048², at 1:1 "
                    "(colour beside the lit relief), beside the 512-px view of the whole tile. Regenerate with "
                    "`scripts/gallery_crops` (bark and mud by default), then `scripts/gallery`.\n\n"
                    "| preset | whole tile at 512 px | 2048², middle 512 px at 1:1 |\n|---|---|---|\n")
            for c in crops:
                folder = c[: -len("-2048.jpg")]
                f.write(f"| `{folder}` | ![{folder}]({folder}.jpg) | ![{folder} at 2048](crops/{c}) |\n")
        renders = sorted(c for c in os.listdir(os.path.join(out, "cycles")) if c.endswith(".jpg")) \
            if os.path.isdir(os.path.join(out, "cycles")) else []
        if renders:
            f.write("\n## Rendered in Blender Cycles\n\nThe maps baked at 2048² on a plane of the tile's size, displaced "
                    "by the height map at the report's `displacement_scale_m`, lit by a low sun from the upper left: "
                    "the middle 35 % of the tile, the raster grooves (the bake before the crack curves) on the "
                    "left, the crack-curve grooves on the right. Regenerate with `scripts/gallery_cycles` "
                    "(mud and bark by default; needs Blender), then `scripts/gallery`.\n\n"
                    "| preset | raster grooves (left), crack curves (right) |\n|---|---|\n")
            for c in renders:
                folder = c[: -len(".jpg")]
                f.write(f"| `{folder}` | ![{folder} in Cycles](cycles/{c}) |\n")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2])

"""Renders baked texture sets in Blender Cycles with real displacement (a manual check, not in CTest).

    build/crackle bake mud --size 2048 --out /tmp/cy/mud --json /tmp/cy/mud.json
    blender -b --factory-startup --python tests/tools/cycles_maps.py -- \
        --out /tmp/cy/mud.png [--size 1024] [--samples 24] [--crop 0.25] /tmp/cy/mud.json

Each report names its maps (files) and gives the tile's size in metres (tile_size_m) and the
height's scale (displacement_scale_m). The tile becomes a plane of that size, subdivided to one
vertex per map pixel (at most 2048 across) and displaced by the height map at that scale (a
Displace modifier, Midlevel 0), with the colour, roughness and (for detail finer than the
vertices) NormalGL maps on a Principled BSDF as docs/user-guide.md wires them. A low sun from the
upper left (25 degrees up), a camera straight down, orthographic; --crop shows that share of the
tile's width around its middle.

Debian 12: apt-get install blender.
"""
import bpy, math, json, os, sys

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []


def take(flag, default, kind=str):
    if flag in args:
        i = args.index(flag)
        value = kind(args[i + 1])
        del args[i:i + 2]
        return value
    return default


out = take("--out", "/tmp/cycles_maps.png")
size = take("--size", 1024, int)
samples = take("--samples", 24, int)
crop = take("--crop", 1.0, float)
reports = args
if len(reports) != 1:
    sys.exit("cycles_maps.py: give one bake report (the --json of crackle bake)")


def map_file(report, name):
    for f in report["files"]:
        if f.endswith("_" + name + ".png"):
            return f
    sys.exit(f"cycles_maps.py: the report has no {name} map (bake with --maps all)")


def image(path, colour):
    img = bpy.data.images.load(path)
    img.colorspace_settings.name = "sRGB" if colour else "Non-Color"
    return img


def tile_object(report, offset_x):
    """The tile as a displaced, textured plane centred at (offset_x, 0); returns its size in metres."""
    width_m, height_m = report["tile_size_m"]
    pixels = report["size"]
    verts = min(pixels, 2048)
    bpy.ops.mesh.primitive_grid_add(x_subdivisions=verts, y_subdivisions=max(2, round(verts * height_m / width_m)),
                                    size=1.0, calc_uvs=True)
    obj = bpy.context.active_object
    obj.scale = (width_m, height_m, 1.0)
    obj.location = (offset_x, 0.0, 0.0)
    bpy.ops.object.transform_apply(scale=True)
    tex = bpy.data.textures.new("height", type="IMAGE")
    tex.image = image(map_file(report, "Displacement"), False)
    tex.extension = "EXTEND"
    mod = obj.modifiers.new("displace", "DISPLACE")
    mod.texture = tex
    mod.texture_coords = "UV"
    mod.strength = report["displacement_scale_m"]
    mod.mid_level = 0.0
    bpy.ops.object.shade_smooth()

    mat = bpy.data.materials.new("crackle")
    mat.use_nodes = True
    nodes, links = mat.node_tree.nodes, mat.node_tree.links
    bsdf = nodes["Principled BSDF"]
    colour = nodes.new("ShaderNodeTexImage")
    colour.image = image(map_file(report, "Color"), True)
    links.new(colour.outputs["Color"], bsdf.inputs["Base Color"])
    rough = nodes.new("ShaderNodeTexImage")
    rough.image = image(map_file(report, "Roughness"), False)
    links.new(rough.outputs["Color"], bsdf.inputs["Roughness"])
    normal = nodes.new("ShaderNodeTexImage")
    normal.image = image(map_file(report, "NormalGL"), False)
    normal_map = nodes.new("ShaderNodeNormalMap")
    links.new(normal.outputs["Color"], normal_map.inputs["Color"])
    links.new(normal_map.outputs["Normal"], bsdf.inputs["Normal"])
    obj.data.materials.append(mat)
    return width_m, height_m


bpy.ops.wm.read_factory_settings(use_empty=True)
scene = bpy.context.scene
report = json.load(open(reports[0]))
width_m, height_m = tile_object(report, 0.0)

cam_data = bpy.data.cameras.new("camera")
cam_data.type = "ORTHO"
cam_data.ortho_scale = max(width_m, height_m) * crop
cam = bpy.data.objects.new("camera", cam_data)
cam.location = (0.0, 0.0, 1.0)
scene.collection.objects.link(cam)
scene.camera = cam

sun_data = bpy.data.lights.new("sun", type="SUN")
sun_data.energy = 4.0
sun_data.angle = math.radians(1.0)
sun = bpy.data.objects.new("sun", sun_data)
# Light from the upper left of the image (-x, +y), 25 degrees above the horizon.
sun.rotation_euler = (math.radians(65.0), 0.0, math.radians(-135.0))
scene.collection.objects.link(sun)
world = bpy.data.worlds.new("world")
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.15
scene.world = world

scene.render.engine = "CYCLES"
scene.cycles.device = "CPU"
scene.cycles.samples = samples
scene.cycles.use_denoising = False
scene.view_settings.view_transform = "Standard"
scene.render.resolution_x = size if width_m >= height_m else max(1, round(size * width_m / height_m))
scene.render.resolution_y = size if height_m >= width_m else max(1, round(size * height_m / width_m))
scene.render.filepath = out
bpy.ops.render.render(write_still=True)
print("cycles_maps.py: wrote", out)

"""Imports crackle exports into Blender and prints what arrived (a manual check, not in CTest).

    build/crackle bake mud --size 256 --mesh glb,gltf,obj --out /tmp/blend   # likewise bark, --pieces
    blender -b --factory-startup --python tests/tools/blender_import.py -- \
        [--render /tmp/blend/renders] /tmp/blend/mud.glb /tmp/blend/bark_split.obj ...

For each file: objects, vertices and faces, the world bounding box (Blender is Z-up: a plane
lies flat in Z, a trunk stands along Z), the objects' "fragment" property (split glTF),
materials with their image nodes, colour spaces and the sockets they feed, and with --render a
256 px Cycles image (32 samples) <render dir>/<file name>.png. The OBJ importer runs with its defaults
(forward -Z, up +Y), as a user would. docs/exports.md shows what to expect.

Debian 12: apt-get install blender python3-numpy. Blender 3.4's glTF importer still uses
numpy.bool, which numpy 1.24 removed; the first lines below put it back.
"""
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # Blender 3.4 importer vs numpy 1.24 (Debian 12)
import bpy, math, os, sys
from mathutils import Vector

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
render_dir = None
if "--render" in args:
    i = args.index("--render")
    render_dir = args[i + 1]
    del args[i:i + 2]


def world_bounds(objects):
    lo, hi = Vector((1e9,) * 3), Vector((-1e9,) * 3)
    for o in objects:
        for v in o.data.vertices:
            p = o.matrix_world @ v.co
            lo = Vector(min(a, b) for a, b in zip(lo, p))
            hi = Vector(max(a, b) for a, b in zip(hi, p))
    return lo, hi


def describe_materials():
    for m in bpy.data.materials:
        if not m.use_nodes:
            continue
        for n in m.node_tree.nodes:
            if n.type != 'TEX_IMAGE' or not n.image:
                continue
            feeds = []
            for link in m.node_tree.links:
                if link.from_node == n:
                    to = link.to_node
                    # follow one step through Separate RGB / Normal Map nodes to the shader input
                    onward = [f"{l.to_node.name}.{l.to_socket.name}" for l in m.node_tree.links if l.from_node == to]
                    feeds.append(f"{link.from_socket.name}->{to.name}.{link.to_socket.name}"
                                 + (f"->{','.join(onward)}" if onward and to.type != 'BSDF_PRINCIPLED' else ""))
            print(f"  material {m.name}: image {n.image.name} ({n.image.size[0]}x{n.image.size[1]}) "
                  f"colourspace {n.image.colorspace_settings.name}: {'; '.join(feeds) or 'unlinked'}")


def render(path, lo, hi):
    scene = bpy.context.scene
    centre, size = (lo + hi) / 2, (hi - lo).length
    cam_data = bpy.data.cameras.new("check")
    cam = bpy.data.objects.new("check", cam_data)
    scene.collection.objects.link(cam)
    direction = Vector((0.9, -1.3, 0.8)).normalized()
    cam.location = centre + direction * size * 1.4
    cam.rotation_euler = (-direction).to_track_quat('-Z', 'Y').to_euler()
    cam_data.lens = 50
    scene.camera = cam
    sun_data = bpy.data.lights.new("sun", 'SUN')
    sun_data.energy = 4.0
    sun_data.angle = math.radians(3)
    sun = bpy.data.objects.new("sun", sun_data)
    sun.rotation_euler = (math.radians(50), 0, math.radians(-40))  # low sun: the relief shows
    scene.collection.objects.link(sun)
    world = bpy.data.worlds.new("check")
    world.color = (0.05, 0.05, 0.06)
    scene.world = world
    scene.render.engine = 'CYCLES'
    scene.cycles.device = 'CPU'
    scene.cycles.samples = 32
    scene.cycles.use_denoising = False  # Debian's Blender has no OpenImageDenoise
    scene.render.resolution_x = scene.render.resolution_y = 256
    scene.render.resolution_percentage = 100
    scene.render.filepath = path
    bpy.ops.render.render(write_still=True)
    print(f"  render {path}")


for path in args:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith(".obj"):
        r = bpy.ops.wm.obj_import(filepath=path)
    else:
        r = bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.data.objects if o.type == 'MESH']
    nv = sum(len(o.data.vertices) for o in meshes)
    nf = sum(len(o.data.polygons) for o in meshes)
    lo, hi = world_bounds(meshes)
    ext = hi - lo
    tagged = [o for o in meshes if "fragment" in o.keys()]
    uv = all(len(o.data.uv_layers) > 0 for o in meshes)
    print(f"RESULT {os.path.basename(path)} {r} objects {len(meshes)} verts {nv} faces {nf} uv {uv}")
    print(f"  bounds min ({lo.x:.4f}, {lo.y:.4f}, {lo.z:.4f}) max ({hi.x:.4f}, {hi.y:.4f}, {hi.z:.4f}) "
          f"extent ({ext.x:.4f}, {ext.y:.4f}, {ext.z:.4f}) m")
    names = sorted(o.name for o in meshes)
    print(f"  objects {names[:3]}{' ...' if len(names) > 3 else ''}; with a fragment property: {len(tagged)}"
          + (f" (e.g. {tagged[0].name}: {tagged[0]['fragment']})" if tagged else ""))
    describe_materials()
    if render_dir:
        os.makedirs(render_dir, exist_ok=True)
        render(os.path.join(render_dir, os.path.basename(path).replace(".", "_") + ".png"), lo, hi)

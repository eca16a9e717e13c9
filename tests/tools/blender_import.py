"""Imports crackle exports into Blender and prints what arrived (a manual check, not in CTest).

    build/crackle export mud --format glb --out /tmp/blend/mud.glb   # likewise .gltf and .obj
    blender -b --factory-startup --python tests/tools/blender_import.py -- /tmp/blend/mud.glb ...

Debian 12: apt-get install blender python3-numpy. Blender 3.4's glTF importer still uses
numpy.bool, which numpy 1.24 removed; the first lines below put it back.
"""
import numpy
if not hasattr(numpy, "bool"): numpy.bool = bool  # Blender 3.4 importer vs numpy 1.24 (Debian 12)
import bpy, sys
paths = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
for path in paths:
    bpy.ops.wm.read_factory_settings(use_empty=True)
    if path.endswith(".obj"):
        r = bpy.ops.wm.obj_import(filepath=path)
    else:
        r = bpy.ops.import_scene.gltf(filepath=path)
    meshes = [o for o in bpy.data.objects if o.type == 'MESH']
    nv = sum(len(o.data.vertices) for o in meshes); nf = sum(len(o.data.polygons) for o in meshes)
    mats = [m.name for m in bpy.data.materials]
    imgs = [(i.name, i.size[0], i.size[1]) for i in bpy.data.images]
    uv = all(len(o.data.uv_layers) > 0 for o in meshes)
    print("RESULT", path, r, "objects", len(meshes), "verts", nv, "faces", nf, "uv", uv, "materials", mats, "images", imgs)

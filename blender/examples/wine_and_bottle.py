"""A glass of red wine and a green bottle on a table, built by script, rendered by Cycles and by Bouguer
from the same .blend, with the mean CIEDE2000 between them (docs/blender.md):

    blender -b --factory-startup --python blender/examples/wine_and_bottle.py -- build out/wine [WIDTH SPP]

Writes OUT/scene.blend, OUT/cycles.png, OUT/bouguer.png (Blender's Standard view transform) and
OUT/delta_e.txt. The surfaces and lights agree; the thick coloured glass and the wine rightly differ:
Cycles colours them by its Volume Absorption in three channels, Bouguer's wine is the library's
measured red wine (docs/materials.md) at its index 1.343, nested in the glass by priority."""
import math
import os
import pathlib
import sys

import bpy
import numpy as np

args = sys.argv[sys.argv.index("--") + 1:] if "--" in sys.argv else []
BUILD = pathlib.Path(args[0] if args else "build").resolve()
OUT = pathlib.Path(args[1] if len(args) > 1 else "out/wine").resolve()
WIDTH = int(args[2]) if len(args) > 2 else 320
SPP = int(args[3]) if len(args) > 3 else 256
sys.path.insert(0, str(BUILD))
sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))
import bouguer  # noqa: E402
import bouguer_blender  # noqa: E402

bouguer_blender.register()


def lathe(name, profile, segments=96):
    """A closed solid of revolution about z from a profile [(r, z), ...] that starts and ends on the axis."""
    verts, faces = [], []
    inner = profile[1:-1]
    for i in range(segments):
        a = 2 * math.pi * i / segments
        verts += [(r * math.cos(a), r * math.sin(a), z) for r, z in inner]
    bottom, top = len(verts), len(verts) + 1
    verts += [(0, 0, profile[0][1]), (0, 0, profile[-1][1])]
    n = len(inner)
    for i in range(segments):
        j = (i + 1) % segments
        for k in range(n - 1):
            faces.append((i * n + k, j * n + k, j * n + k + 1, i * n + k + 1))
        faces.append((bottom, j * n, i * n))
        faces.append((top, i * n + n - 1, j * n + n - 1))
    mesh = bpy.data.meshes.new(name)
    mesh.from_pydata(verts, [], faces)
    mesh.update()
    mesh.normals_make_consistent(inside=False) if hasattr(mesh, "normals_make_consistent") else None
    obj = bpy.data.objects.new(name, mesh)
    bpy.context.scene.collection.objects.link(obj)
    for p in mesh.polygons:
        p.use_smooth = True
    if hasattr(mesh, "use_auto_smooth"):
        mesh.use_auto_smooth, mesh.auto_smooth_angle = True, math.radians(40)
    return obj


def shader(name, kind, **inputs):
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    t = m.node_tree
    for n in list(t.nodes):
        if n.type != "OUTPUT_MATERIAL":
            t.nodes.remove(n)
    node = t.nodes.new(kind)
    for k, v in inputs.items():
        node.inputs[k].default_value = v
    t.links.new(node.outputs[0], t.nodes["Material Output"].inputs["Surface"])
    return m


def with_volume(m, colour, density):
    t = m.node_tree
    v = t.nodes.new("ShaderNodeVolumeAbsorption")
    v.inputs["Color"].default_value, v.inputs["Density"].default_value = (*colour, 1), density
    t.links.new(v.outputs[0], t.nodes["Material Output"].inputs["Volume"])
    return m


def build():
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = bpy.context.scene
    s.unit_settings.scale_length = 0.01  # centimetres
    s.render.resolution_x, s.render.resolution_y, s.render.resolution_percentage = WIDTH, WIDTH * 3 // 4, 100
    s.view_settings.view_transform = "Standard"
    s.cycles.device, s.cycles.samples, s.cycles.use_denoising = "CPU", SPP, False
    s.cycles.pixel_filter_type, s.cycles.filter_width = "BOX", 1.0
    s.cycles.max_bounces = s.cycles.transmission_bounces = s.cycles.transparent_max_bounces = 32
    s.bouguer.integrator, s.bouguer.spectral, s.bouguer.spp, s.bouguer.max_depth = "path", "hero", SPP, 32
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    bg = world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value, bg.inputs["Strength"].default_value = (0.8, 0.85, 1.0, 1), 0.4
    s.world = world
    # The table and a wall behind it.
    bpy.ops.mesh.primitive_plane_add(size=200)
    bpy.context.object.data.materials.append(shader("wood", "ShaderNodeBsdfDiffuse", Color=(0.42, 0.26, 0.15, 1)))
    bpy.ops.mesh.primitive_plane_add(size=200, location=(0, 40, 0), rotation=(math.radians(90), 0, 0))
    bpy.context.object.data.materials.append(shader("wall", "ShaderNodeBsdfDiffuse", Color=(0.75, 0.73, 0.7, 1)))
    # A wine glass (cm): foot, stem, bowl; 2 mm walls.
    glass = lathe("glass", [(0, 0), (3.5, 0), (3.5, 0.3), (0.5, 0.5), (0.4, 7), (1.5, 8), (3.6, 11), (3.8, 14),
                            (3.9, 17), (3.7, 17), (3.6, 14), (3.4, 11), (1.4, 8.2), (0, 8.2)])
    glass.location = (-4, 0, 0)
    g = shader("glass", "ShaderNodeBsdfGlass", IOR=1.5, Roughness=0.0, Color=(1, 1, 1, 1))
    g.bouguer.use_priority, g.bouguer.priority = True, 1
    glass.data.materials.append(g)
    # Its wine, 0.5 mm into the glass's wall (nested media: the wine's priority is higher).
    wine = lathe("wine", [(0, 8.15), (1.45, 8.15), (3.45, 11), (3.62, 13.5), (0, 13.5)])
    wine.location = (-4, 0, 0)
    w = with_volume(shader("wine", "ShaderNodeBsdfGlass", IOR=1.343, Roughness=0.0, Color=(1, 1, 1, 1)),
                    (0.55, 0.02, 0.08), 0.9)
    w.bouguer.source, w.bouguer.library, w.bouguer.ior_source = "LIBRARY", "red-wine", "DEFAULT"
    w.bouguer.use_priority, w.bouguer.priority = True, 2
    wine.data.materials.append(w)
    # A green bottle: 3 mm walls, empty.
    bottle = lathe("bottle", [(0, 0), (3.6, 0), (3.7, 0.5), (3.7, 18), (3.0, 21), (1.3, 24), (1.3, 29), (1.0, 29),
                              (1.0, 24.3), (2.7, 21.2), (3.4, 18), (3.4, 0.6), (0, 0.6)])
    bottle.location = (5, 6, 0)
    bottle.data.materials.append(with_volume(shader("green glass", "ShaderNodeBsdfGlass", IOR=1.52, Roughness=0.0,
                                                    Color=(1, 1, 1, 1)), (0.35, 0.75, 0.3), 0.8))
    # A soft key light and the camera.
    light = bpy.data.lights.new("key", "AREA")
    light.energy, light.shape, light.size, light.size_y = 2.0e4, "RECTANGLE", 40, 25
    key = bpy.data.objects.new("key", light)
    key.location, key.rotation_euler = (-30, -30, 60), (math.radians(35), 0, math.radians(-40))
    s.collection.objects.link(key)
    cam = bpy.data.cameras.new("camera")
    cam.lens = 50
    camera = bpy.data.objects.new("camera", cam)
    camera.location, camera.rotation_euler = (8, -55, 22), (math.radians(76), 0, math.radians(8))
    s.collection.objects.link(camera)
    s.camera = camera
    return s


def render(s, engine):
    s.render.engine = engine
    s.render.image_settings.file_format = "OPEN_EXR"
    s.render.filepath = str(OUT / f"{engine.lower()}.exr")
    bpy.ops.render.render(write_still=True)
    image = bpy.data.images.load(s.render.filepath)
    (w, h), c = image.size, image.channels
    px = np.empty(w * h * c, dtype=np.float32)
    image.pixels.foreach_get(px)
    s.render.image_settings.file_format = "PNG"  # save_render writes with the scene's view transform
    image.save_render(str(OUT / f"{engine.lower()}.png"), scene=s)
    return px.reshape(h, w, c)[::-1, :, :3].copy()


OUT.mkdir(parents=True, exist_ok=True)
scene = build()
bpy.ops.wm.save_as_mainfile(filepath=str(OUT / "scene.blend"))
cycles = render(scene, "CYCLES")
ours = render(scene, "BOUGUER")
d = bouguer.compare(ours, cycles)
text = f"mean dE00 Bouguer-Cycles {d['mean']:.2f} (p95 {d['p95']:.2f}), {WIDTH} px wide, {SPP} samples\n"
(OUT / "delta_e.txt").write_text(text)
np.save(OUT / "delta_e.npy", d["delta_e"])
print(text, end="")
sys.stdout.flush()
os._exit(0)

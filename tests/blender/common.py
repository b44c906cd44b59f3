"""Shared pieces of the tests inside Blender: run as
    blender -b --factory-startup --python-exit-code 1 --python tests/blender/<test>.py -- <build dir>
Scenes are built by script at test time and rendered by Cycles (CPU) and by Bouguer through the add-on's
engine, both into 32-bit OpenEXR files read back as linear arrays (no view transform)."""
import os
import pathlib
import sys
import tempfile
import time
import traceback

import bpy
import numpy as np

SOURCE = pathlib.Path(__file__).resolve().parents[2]
BUILD = pathlib.Path(sys.argv[sys.argv.index("--") + 1] if "--" in sys.argv else SOURCE / "build").resolve()
OUT = pathlib.Path(tempfile.mkdtemp(prefix="bouguer-blender-"))
SKIP = 77  # ctest's SKIP_RETURN_CODE for these tests


def setup():
    """The module and the add-on, or exit 77 (skip) where the module was not built."""
    if not list(BUILD.glob("bouguer.cpython-*.so")):
        print(f"SKIP: the bouguer Python module was not built in {BUILD}")
        sys.exit(SKIP)
    sys.path.insert(0, str(BUILD))
    sys.path.insert(0, str(SOURCE / "blender"))
    import bouguer_blender
    bouguer_blender.register()
    import bouguer
    return bouguer


def new_scene(resolution=(16, 16)):
    bpy.ops.wm.read_factory_settings(use_empty=True)
    s = bpy.context.scene
    s.render.resolution_x, s.render.resolution_y = resolution
    s.render.resolution_percentage = 100
    s.view_settings.view_transform = "Standard"
    s.render.image_settings.file_format = "OPEN_EXR"
    s.render.image_settings.color_depth = "32"
    s.cycles.device = "CPU"
    s.cycles.use_denoising = False
    s.cycles.pixel_filter_type = "BOX"  # a box filter one pixel wide, as Bouguer's
    s.cycles.filter_width = 1.0
    s.cycles.light_sampling_threshold = 0.0
    s.cycles.max_bounces = s.cycles.diffuse_bounces = s.cycles.glossy_bounces = 32
    s.cycles.transmission_bounces = s.cycles.volume_bounces = s.cycles.transparent_max_bounces = 32
    s.cycles.sample_clamp_indirect = 0.0
    s.cycles.use_adaptive_sampling = False
    s.bouguer.integrator = "path"
    s.bouguer.spectral = "rgb3"
    world = bpy.data.worlds.new("World")
    world.use_nodes = True
    world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.0
    s.world = world
    return s


def material(name, shader, output="Surface", **inputs):
    """A material whose surface (or volume) is one shader node with constant inputs."""
    m = bpy.data.materials.new(name)
    m.use_nodes = True
    tree = m.node_tree
    for n in list(tree.nodes):
        if n.type != "OUTPUT_MATERIAL":
            tree.nodes.remove(n)
    node = tree.nodes.new(shader)
    for k, v in inputs.items():
        node.inputs[k].default_value = v
    tree.links.new(node.outputs[0], tree.nodes["Material Output"].inputs[output])
    return m


def diffuse(name="white", colour=(0.8, 0.8, 0.8)):
    return material(name, "ShaderNodeBsdfDiffuse", Color=(*colour, 1.0))


def add_mesh(primitive, material_=None, **kwargs):
    getattr(bpy.ops.mesh, f"primitive_{primitive}_add")(**kwargs)
    obj = bpy.context.object
    if material_ is not None:
        obj.data.materials.append(material_)
    return obj


def add_camera(scene, location, rotation=(0, 0, 0), kind="ORTHO", **data):
    cam = bpy.data.cameras.new("Camera")
    cam.type = kind
    for k, v in data.items():
        setattr(cam, k, v)
    obj = bpy.data.objects.new("Camera", cam)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    scene.camera = obj
    return obj


def add_light(scene, kind, location=(0, 0, 1), rotation=(0, 0, 0), **data):
    light = bpy.data.lights.new(kind.lower(), kind)
    for k, v in data.items():
        setattr(light, k, v)
    obj = bpy.data.objects.new(kind.lower(), light)
    obj.location = location
    obj.rotation_euler = rotation
    scene.collection.objects.link(obj)
    return obj


def render(scene, engine, name, samples=64):
    """The image of a render as a float (H, W, 3) array, row 0 at the top; its seconds."""
    scene.render.engine = engine
    scene.cycles.samples = samples
    scene.bouguer.spp = samples
    scene.render.filepath = str(OUT / f"{name}.exr")
    start = time.monotonic()
    bpy.ops.render.render(write_still=True)
    seconds = time.monotonic() - start
    image = bpy.data.images.load(scene.render.filepath)
    (w, h), channels = image.size, image.channels
    px = np.empty(w * h * channels, dtype=np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    return px.reshape(h, w, channels)[::-1, :, :3].copy(), seconds


class Checks:
    """Runs test functions, prints each result, and exits 1 if any failed."""

    def __init__(self):
        self.failed = []

    def run(self, tests):
        start = time.monotonic()
        for test in tests:
            t0 = time.monotonic()
            try:
                test()
                print(f"PASS {test.__name__} ({time.monotonic() - t0:.1f} s)")
            except Exception:
                traceback.print_exc()
                print(f"FAIL {test.__name__}")
                self.failed.append(test.__name__)
        print(f"{len(tests) - len(self.failed)} of {len(tests)} passed in {time.monotonic() - start:.1f} s")
        sys.stdout.flush()
        os._exit(1 if self.failed else 0)

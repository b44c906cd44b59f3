"""Camera framing equal to the pixel: an emitting object's silhouette in Cycles and in Bouguer through
the add-on, perspective (sensor fit AUTO, HORIZONTAL, VERTICAL; landscape and portrait; shift) and
orthographic (with shift). Both renderers use a one-pixel box filter, so a pixel's value is the
fraction of it the object covers. The tolerance: the mean difference over the silhouette's edge
pixels below 0.05 and none above 0.25 (256 stratified samples give a coverage noise near 0.03). It
catches half a pixel anywhere (an edge pixel's coverage then moves by about 0.5), a fov taken across
the wrong side, a shift in the wrong unit or sign."""
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402

bouguer = common.setup()


def silhouette_scene(resolution, kind, **camera):
    s = common.new_scene(resolution)
    emit = common.material("emit", "ShaderNodeEmission", Color=(1, 1, 1, 1), Strength=1.0)
    cube = common.add_mesh("cube", emit, size=1.0, location=(0.3, -0.2, 0.1), rotation=(0.4, 0.2, 0.7))
    cube.scale = (1.0, 0.6, 0.8)
    common.add_mesh("uv_sphere", emit, radius=0.35, location=(-0.9, 0.5, 0.4), segments=48, ring_count=24)
    common.add_camera(s, (4.0, -5.0, 3.0), (math.radians(63), 0, math.radians(38)), kind=kind, **camera)
    return s


def with_instances(scene):
    """An Array modifier on the cube and a collection instanced twice: modifiers applied and instances
    at their own matrices (the silhouettes move if either is lost)."""
    import bpy
    cube = scene.objects["Cube"]
    array = cube.modifiers.new("array", "ARRAY")
    array.count, array.relative_offset_displace = 2, (0.0, 1.6, 0.0)
    collection = bpy.data.collections.new("pair")
    sphere = scene.objects["Sphere"]
    scene.collection.objects.unlink(sphere)
    collection.objects.link(sphere)
    for i, location in enumerate([(0.0, 0.0, 0.0), (1.2, -1.5, 0.2)]):
        inst = bpy.data.objects.new(f"instance {i}", None)
        inst.instance_type, inst.instance_collection = "COLLECTION", collection
        inst.location = location
        inst.scale = (1.0, 1.0, 1.0 + 0.5 * i)
        scene.collection.objects.link(inst)
    return scene


def compare(name, scene):
    cycles, _ = common.render(scene, "CYCLES", f"{name}-cycles", 256)
    ours, _ = common.render(scene, "BOUGUER", f"{name}-bouguer", 256)
    a, b = cycles.mean(axis=2), ours.mean(axis=2)
    edge = ((a > 0.02) & (a < 0.98)) | ((b > 0.02) & (b < 0.98))
    inside = (a > 0.5).sum()
    d = np.abs(a - b)
    print(f"  {name}: {inside} pixels inside, {edge.sum()} on the edge, mean difference there {d[edge].mean():.4f}, "
          f"largest {d.max():.3f}")
    assert inside > 40 and (a < 0.5).sum() > 40, f"{name}: the silhouette does not sit inside the frame"
    assert d[edge].mean() < 0.05 and d.max() < 0.25, f"{name}: the silhouettes differ"


def test_perspective_landscape_auto():
    compare("persp-auto", silhouette_scene((48, 32), "PERSP", lens=35.0, shift_x=0.1, shift_y=-0.05))


def test_perspective_portrait_auto():
    compare("persp-portrait", silhouette_scene((32, 48), "PERSP", lens=35.0, shift_x=-0.05, shift_y=0.1))


def test_perspective_vertical_fit():
    compare("persp-vertical", silhouette_scene((48, 32), "PERSP", lens=30.0, sensor_fit="VERTICAL",
                                               sensor_height=20.0, shift_y=0.08))


def test_perspective_horizontal_fit_portrait():
    compare("persp-horizontal", silhouette_scene((32, 48), "PERSP", lens=45.0, sensor_fit="HORIZONTAL",
                                                 sensor_width=30.0, shift_x=0.07))


def test_orthographic_with_shift():
    compare("ortho", silhouette_scene((48, 32), "ORTHO", ortho_scale=3.5, shift_x=0.12, shift_y=0.05))


def test_modifiers_and_instances():
    compare("instances", with_instances(silhouette_scene((48, 32), "ORTHO", ortho_scale=5.0)))


common.Checks().run([test_perspective_landscape_auto, test_perspective_portrait_auto, test_perspective_vertical_fit,
                     test_perspective_horizontal_fit_portrait, test_orthographic_with_shift, test_modifiers_and_instances])

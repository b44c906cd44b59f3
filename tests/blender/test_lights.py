"""Irradiance on a diffuse plane under each Blender light type and the world: Bouguer through the
add-on against Cycles, in the same run. A white (0.8) plane seen from above by an orthographic camera;
the mean pixel of each is 0.8 E / pi. The tolerance, 2 %, is the issue's; Cycles' noise here is below
0.3 % (64 samples of 256 pixels, a smooth integrand) and the two renderers' pixel footprints are the
same. It catches a wrong conversion of Blender's watts: 1/pi against 1/4 for area lights is 27 %, a
missing unit scale or a light pointing the wrong way much more."""
import math
import sys

import numpy as np

sys.path.insert(0, __import__("os").path.dirname(__file__))
import common  # noqa: E402

bouguer = common.setup()
TOLERANCE = 0.02


def plane_under(light_kind, unit_scale=1.0, **light):
    s = common.new_scene()
    if unit_scale != 1.0:
        s.unit_settings.scale_length = unit_scale
    common.add_mesh("plane", common.diffuse(), size=4)
    # Below the lights: Bouguer's area lights are emitting surfaces, opaque from behind, where Cycles'
    # are not seen by camera rays (docs/blender.md). The centre of the plane, where the spot's profile
    # is flat: Cycles 3.4's spot multiplies its smoothstep by the cosine off the axis, Bouguer's not.
    common.add_camera(s, (0, 0, 0.5), kind="ORTHO", ortho_scale=0.1)
    if light_kind == "WORLD":
        s.world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.3, 0.5, 0.7, 1)
        s.world.node_tree.nodes["Background"].inputs["Strength"].default_value = 1.5
    else:
        common.add_light(s, light_kind, **light)
    return s


def compare(name, scene, samples=64):
    cycles, tc = common.render(scene, "CYCLES", f"{name}-cycles", samples)
    ours, tb = common.render(scene, "BOUGUER", f"{name}-bouguer", samples)
    c, b = cycles.mean(axis=(0, 1)), ours.mean(axis=(0, 1))
    ratio = b / c
    print(f"  {name}: Cycles {np.round(c, 5)} ({tc:.2f} s), Bouguer {np.round(b, 5)} ({tb:.2f} s), "
          f"ratio {np.round(ratio, 4)}")
    assert np.all(c > 1e-3), f"{name}: Cycles' plane is black"
    assert np.all(np.abs(ratio - 1) < TOLERANCE), f"{name}: Bouguer/Cycles = {ratio}"


def test_point():
    compare("point", plane_under("POINT", location=(0.1, 0, 1), energy=100, shadow_soft_size=0))


def test_point_with_a_radius():
    compare("point-radius", plane_under("POINT", location=(0.1, 0, 1), energy=100, shadow_soft_size=0.05))


def test_point_with_a_radius_casts_cycles_soft_shadow():
    # A cube between a point light of radius 0.25 and the plane. From the plane's centre the lamp
    # subtends 9.6 degrees and the cube's bottom face 8.7 each way, so the shadow has no umbra: about 7 %
    # of the lamp shows past the face's sides. A point would leave the middle black and the edge sharp.
    # Cycles' lamp is a disk facing the point it lights, ours a sphere: the same disk from everywhere,
    # but the sphere's irradiance is I/d^2 and the disk's I/(d^2 + r^2), so each image is read against
    # its own lit corner (4 x 4 pixels 0.4 m from the penumbra's edge): the shapes of the shadows are
    # compared, and the corners' ratio against 1 + r^2/d^2 (the radiance conversion: Cycles' 1/4 for
    # 1/pi would be 27 % off). Blocks of 4 x 4 pixels at 2048 samples (measured, two seeds each: a
    # block's standard error 0.0008 of the lit corner in Cycles, 0.0018 in Bouguer; the renderers
    # 0.017-0.019 apart at worst, most of it the sphere's cone, asin(r/d), 1.4 % wider than the
    # disk's, atan(r/d)). The tolerance, 0.04, is that and 10 standard errors of the two; a point
    # leaves the middle blocks at 0.01 where Cycles has 0.71.
    s = common.new_scene((32, 32))
    common.add_mesh("plane", common.diffuse(), size=4)
    common.add_mesh("cube", common.diffuse("grey", (0.5, 0.5, 0.5)), size=0.2, location=(0, 0, 0.75))
    common.add_camera(s, (0, 0, 0.5), kind="ORTHO", ortho_scale=1.6)
    height, radius = 1.5, 0.25
    common.add_light(s, "POINT", location=(0, 0, height), energy=200, shadow_soft_size=radius)
    cycles, tc = common.render(s, "CYCLES", "penumbra-cycles", 2048)
    ours, tb = common.render(s, "BOUGUER", "penumbra-bouguer", 2048)
    lit_c, lit_b = cycles[:4, :4].mean(), ours[:4, :4].mean()
    corner_d2 = height ** 2 + 2 * 0.7 ** 2  # the corner's centre, 0.7 m off each axis
    expected, corner = 1 + radius ** 2 / corner_d2, lit_b / lit_c
    blocks = lambda im, lit: im.mean(axis=2).reshape(8, 4, 8, 4).mean(axis=(1, 3)) / lit
    worst = np.abs(blocks(cycles, lit_c) - blocks(ours, lit_b)).max()
    centre_c, centre_b = cycles[14:18, 14:18].mean() / lit_c, ours[14:18, 14:18].mean() / lit_b
    print(f"  soft shadow: centre Cycles {centre_c:.4f}, Bouguer {centre_b:.4f} of the lit corner; worst block "
          f"difference {worst:.4f}; corners Bouguer/Cycles {corner:.4f} (1 + r^2/d^2 = {expected:.4f}) "
          f"({tc:.2f} s, {tb:.2f} s)")
    assert centre_c > 0.02, "Cycles' shadow has an umbra: the test's geometry is off"
    assert worst < 0.04, f"the soft shadow differs from Cycles' by {worst:.3f} of the lit corner"
    assert abs(corner - expected) < 0.005, f"the lamp's radiance: corners Bouguer/Cycles {corner:.4f}, not {expected:.4f}"


def test_point_in_centimetres():
    # 1 BU = 1 cm: Cycles ignores the unit, so the intensity is scaled by s^2 to keep its pixels.
    compare("point-cm", plane_under("POINT", unit_scale=0.01, location=(0, 0, 1), energy=100, shadow_soft_size=0))


def test_spot():
    # On the axis, tilted 10 degrees: inside the cone, outside the blend.
    compare("spot", plane_under("SPOT", location=(0, 0.2, 1), rotation=(math.radians(-10), 0, 0), energy=100,
                                shadow_soft_size=0, spot_size=math.radians(60), spot_blend=0.15))


def test_sun():
    compare("sun", plane_under("SUN", rotation=(math.radians(30), 0, 0), energy=2.0, angle=0.0))


def test_area_square():
    compare("area-square", plane_under("AREA", energy=100, shape="SQUARE", size=0.5), samples=256)


def test_area_rectangle():
    compare("area-rectangle", plane_under("AREA", location=(0, 0, 0.7), rotation=(0.3, 0, 0.5), energy=100,
                                          shape="RECTANGLE", size=0.6, size_y=0.2), samples=256)


def test_area_disk():
    compare("area-disk", plane_under("AREA", energy=100, shape="DISK", size=0.5), samples=256)


def test_area_ellipse():
    compare("area-ellipse", plane_under("AREA", energy=100, shape="ELLIPSE", size=0.6, size_y=0.3), samples=256)


def test_world():
    compare("world", plane_under("WORLD"), samples=128)


def environment_scene(rotation):
    s = common.new_scene((32, 24))
    w, h = 64, 32
    u, v = np.meshgrid((np.arange(w) + 0.5) / w, (np.arange(h) + 0.5) / h)
    rgba = np.stack([u, v, 0.5 + 0.4 * np.sin(2 * np.pi * u), np.ones_like(u)], axis=-1).astype(np.float32)
    image = common.bpy.data.images.new("sky", w, h, float_buffer=True, alpha=False)
    image.pixels.foreach_set(rgba.ravel())  # Blender's rows run bottom to top: v up
    image.filepath_raw = str(common.OUT / "sky.exr")
    image.file_format = "OPEN_EXR"
    image.save()
    tree = s.world.node_tree
    env = tree.nodes.new("ShaderNodeTexEnvironment")
    env.image = common.bpy.data.images.load(str(common.OUT / "sky.exr"))
    env.interpolation = "Linear"
    tree.links.new(env.outputs["Color"], tree.nodes["Background"].inputs["Color"])
    tree.nodes["Background"].inputs["Strength"].default_value = 2.0
    s.world.cycles.sampling_method = "NONE"  # only the camera sees the sky: no importance map to build
    common.add_camera(s, (0, 0, 0), rotation, kind="PERSP", lens=20.0)
    return s


def test_environment_map_faces_where_cycles_has_it():
    # The camera sees the sky itself in three directions. An image whose colour runs with u and v shows
    # any turn, mirror or flip of the map as a difference of 0.1 or more; the tolerance, 0.01 mean, is
    # above the two renderers' texel filtering (bilinear both) and far below that.
    for rotation in [(math.radians(90), 0, math.radians(-90)), (math.radians(60), 0, math.radians(150)),
                     (math.radians(120), 0, math.radians(20))]:
        s = environment_scene(rotation)
        cycles, _ = common.render(s, "CYCLES", "sky-cycles", 16)
        ours, _ = common.render(s, "BOUGUER", "sky-bouguer", 16)
        d = np.abs(cycles - ours).mean()
        print(f"  sky towards {np.round(np.degrees(rotation), 0)}: Cycles mean {np.round(cycles.mean(axis=(0, 1)), 3)}, "
              f"Bouguer {np.round(ours.mean(axis=(0, 1)), 3)}, mean difference {d:.4f}")
        assert d < 0.01 * cycles.mean() / 0.5, "the environment map is turned against Cycles'"


common.Checks().run([test_environment_map_faces_where_cycles_has_it, test_point, test_point_with_a_radius,
                     test_point_with_a_radius_casts_cycles_soft_shadow, test_point_in_centimetres, test_spot, test_sun,
                     test_area_square, test_area_rectangle, test_area_disk, test_area_ellipse, test_world])

"""Assets made in Blender and written by Blender's own glTF exporter (io_scene_gltf2, as a user exports
them for other tools), rendered by Bouguer's command line: what #35 found lost on that path.

- A glass sheet made the usual way (Principled BSDF, Transmission 1, no "glTF Material Output" thickness
  group) is exported thin-walled; Bouguer renders it as a thin dielectric sheet. A non-absorbing sheet
  seen face-on before an emitting panel transmits (1 - R)/(1 + R) of it, 0.9231 at n = 1.5, within 1 %
  (4.8 standard errors of the Bernoulli of transmission over 16 px x 1024 samples): an invisible sheet
  (1.0) or one that drops the multiple reflections (1 - R)^2 = 0.9216 is caught only by the first, a
  sheet that reflects twice as much (0.85) by both.
- A glass ball on a red floor under a 500 W point light (about 27 000 cd after the exporter's 683 lm/W):
  the ball is visible (its region of the image differs from the same scene without it), the automatic
  exposure puts the lit floor's PNG values between 10 % grey and white (not clipped: without exposure
  they are 255), and --exposure 1 doubles the PNG's linear values and leaves the EXR byte for byte.
"""
import pathlib
import subprocess
import sys

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parent))
import common  # noqa: E402

import bpy  # noqa: E402
import numpy as np  # noqa: E402

common.setup()
BOUGUER = common.BUILD / "bouguer"


def principled(name, **inputs):
    return common.material(name, "ShaderNodeBsdfPrincipled", **inputs)


def export(path, **options):
    bpy.ops.export_scene.gltf(filepath=str(path), export_format="GLB", export_cameras=True, export_lights=True,
                              use_selection=False, **options)
    return path


def run(*args):
    done = subprocess.run([str(BOUGUER), *map(str, args), "--quiet"], capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return done.stderr


def read_exr(path):
    image = bpy.data.images.load(str(path))
    (w, h), channels = image.size, image.channels
    px = np.empty(w * h * channels, dtype=np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    return px.reshape(h, w, channels)[::-1, :, :3].copy()


def read_png_linear(path):
    """The PNG's 8-bit codes and their sRGB-decoded linear values."""
    image = bpy.data.images.load(str(path))
    image.colorspace_settings.name = "Non-Color"  # the codes as stored, no decoding by Blender
    (w, h), channels = image.size, image.channels
    px = np.empty(w * h * channels, dtype=np.float32)
    image.pixels.foreach_get(px)
    bpy.data.images.remove(image)
    codes = np.round(px.reshape(h, w, channels)[::-1, :, :3] * 255.0)
    v = codes / 255.0
    return codes, np.where(v <= 0.04045, v / 12.92, ((v + 0.055) / 1.055) ** 2.4)


def test_thin_sheet_from_blender_transmits_one_minus_r_over_one_plus_r():
    scene = common.new_scene((4, 4))
    sheet = common.add_mesh("plane", principled("Glass", **{"Base Color": (1, 1, 1, 1), "Transmission": 1.0,
                                                          "Roughness": 0.0, "IOR": 1.5}), size=0.2)
    panel = common.add_mesh("plane", principled("Panel", **{"Base Color": (0, 0, 0, 1), "Emission": (1, 1, 1, 1),
                                                          "Emission Strength": 1.0}), size=2.0, location=(0, 0, -0.5))
    common.add_camera(scene, (0, 0, 1), kind="PERSP", angle=0.05)
    with_sheet = export(common.OUT / "sheet.glb")
    sheet.hide_set(True)
    bpy.data.objects.remove(sheet)
    without = export(common.OUT / "panel.glb")
    assert panel.name in bpy.data.objects
    for glb in (with_sheet, without):
        run("render", glb, "-o", glb.with_suffix(".exr"), "--integrator", "path", "--spectral", "rgb3", "--spp", 1024,
            "--resolution", "4x4", "--auto-exposure", "off", "--seed", 1)
    seen = read_exr(with_sheet.with_suffix(".exr")).mean()
    bare = read_exr(without.with_suffix(".exr")).mean()
    r = ((1.5 - 1) / (1.5 + 1)) ** 2
    expected = (1 - r) / (1 + r)
    print(f"thin sheet exported by Blender: transmits {seen / bare:.4f} of the panel (closed form {expected:.4f})")
    assert bare > 0.5, bare  # the panel is lit: not a ratio of two dark images
    assert abs(seen / bare - expected) < 0.01 * expected, (seen / bare, expected)


def ball_scene(with_ball):
    scene = common.new_scene((64, 48))
    common.add_mesh("plane", principled("Red floor", **{"Base Color": (0.6, 0.05, 0.04, 1), "Roughness": 1.0,
                                                        "Specular": 0.0}), size=10.0)
    if with_ball:
        bpy.ops.mesh.primitive_uv_sphere_add(radius=0.5, location=(0, 0, 0.5), segments=48, ring_count=24)
        bpy.ops.object.shade_smooth()
        bpy.context.object.data.materials.append(principled("Glass", **{"Transmission": 1.0, "Roughness": 0.0}))
    common.add_light(scene, "POINT", location=(1.0, -1.0, 4.0), energy=500.0, shadow_soft_size=0.0)
    common.add_camera(scene, (0, -6, 3), rotation=(1.15, 0, 0), kind="PERSP", lens=35)
    return export(common.OUT / ("ball.glb" if with_ball else "floor.glb"))


def test_glass_ball_from_blender_is_visible_and_exposed():
    ball, floor = ball_scene(True), ball_scene(False)
    for glb in (ball, floor):
        run("render", glb, "-o", glb.with_suffix(".png"), "-o", glb.with_suffix(".exr"), "--spp", 16, "--seed", 2, "--resolution", "64x48")
    plus = common.OUT / "ball_plus1.png"
    run("render", ball, "-o", plus, "-o", common.OUT / "ball_plus1.exr", "--spp", 16, "--seed", 2, "--resolution", "64x48", "--exposure", 1)
    exr_ball, exr_floor = read_exr(ball.with_suffix(".exr")), read_exr(floor.with_suffix(".exr"))
    # Visible: where the ball is, the image is not the floor's (its reflections, the floor seen through
    # it, its shadow); an index-matched, invisible ball changes nothing.
    changed = np.abs(exr_ball - exr_floor).max(axis=2) > 0.1 * exr_floor.max()
    print(f"glass ball from Blender: {changed.sum()} of {changed.size} pixels differ from the floor alone")
    assert changed.sum() > 30, changed.sum()
    # The lit floor: where the floor alone is at least a quarter of its brightest, outside the ball.
    red = exr_floor[:, :, 0]
    lit = (red >= 0.25 * red.max()) & ~changed
    assert lit.sum() > 50, lit.sum()
    assert red.max() > 5.0, red.max()  # unexposed, these pixels would be white (the 600)
    codes, linear = read_png_linear(ball.with_suffix(".png"))
    floor_red = linear[:, :, 0][lit]
    print(f"auto-exposed lit floor: red channel {floor_red.min():.3f} to {floor_red.max():.3f} (linear)")
    assert codes[:, :, 0][lit].max() < 255, "clipped"
    assert floor_red.min() > 0.1, floor_red.min()
    # +1 EV doubles the PNG's linear values (where neither clips nor rounds to black), not the EXR.
    codes_plus, linear_plus = read_png_linear(plus)
    usable = (codes[:, :, 0] >= 40) & (codes_plus[:, :, 0] < 255)
    ratio = linear_plus[:, :, 0][usable] / linear[:, :, 0][usable]
    print(f"+1 EV: PNG ratio {np.median(ratio):.3f} (median of {usable.sum()} pixels)")
    assert usable.sum() > 50 and abs(np.median(ratio) - 2.0) < 0.03, (usable.sum(), np.median(ratio))
    assert (common.OUT / "ball_plus1.exr").read_bytes() == ball.with_suffix(".exr").read_bytes()


common.Checks().run([test_thin_sheet_from_blender_transmits_one_minus_r_over_one_plus_r,
                     test_glass_ball_from_blender_is_visible_and_exposed])

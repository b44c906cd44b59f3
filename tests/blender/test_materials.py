"""Materials and volumes through the add-on, each against Cycles in the same run or against the closed
form where Cycles' number is not physics (docs/blender.md, "Where Bouguer and Cycles differ")."""
import math
import os
import sys

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402

bouguer = common.setup()
RGB3_NM = np.array([700.0, 546.1, 435.8])


# ---- a backlit slab: an orthographic camera looks down through it at a white emitter ----------------

def backlit_slab(make_material, thickness, resolution=(8, 8), unit_scale=1.0):
    s = common.new_scene(resolution)
    material = make_material()
    if unit_scale != 1.0:
        s.unit_settings.scale_length = unit_scale
    emit = common.material("backlight", "ShaderNodeEmission", Color=(1, 1, 1, 1), Strength=1.0)
    common.add_mesh("plane", emit, size=4, location=(0, 0, -1))
    slab = common.add_mesh("cube", material, size=1.0, location=(0, 0, 0))
    slab.scale = (3.0, 3.0, thickness)
    common.add_camera(s, (0, 0, 2), kind="ORTHO", ortho_scale=0.5)
    return s, slab


def transmittance(scene, slab, engine, name, samples):
    """The slab's transmittance: the image through it over the image without it, per channel."""
    through, _ = common.render(scene, engine, f"{name}-{engine.lower()}", samples)
    slab.hide_render = True
    bare, _ = common.render(scene, engine, f"{name}-{engine.lower()}-bare", samples)
    slab.hide_render = False
    return through.mean(axis=(0, 1)) / bare.mean(axis=(0, 1))


def volume_absorption(colour, density):
    return common.material("wine", "ShaderNodeVolumeAbsorption", "Volume", Color=(*colour, 1.0), Density=density)


def test_volume_absorption_slab_is_cycles_per_channel_in_rgb3():
    # Tolerance 1 %: Cycles' homogeneous absorption is exact, and so is Bouguer's; it catches Blender's
    # glTF reading of the colour (sigma_a = -density ln(colour): 0.223 against 0.2 for colour 0.8, 10 %)
    # and a channel order reversed (factors of 2 and more here).
    colour, density = (0.8, 0.5, 0.2), 2.0
    for t in (0.3, 0.9, 1.8):  # the lift's reference length is 1/1.6 units; 1.8 fits below the camera
        expected = np.exp(-density * (1 - np.array(colour)) * t)
        s, slab = backlit_slab(lambda: volume_absorption(colour, density), t)
        cycles = transmittance(s, slab, "CYCLES", f"absorb-{t}", 16)
        ours = transmittance(s, slab, "BOUGUER", f"absorb-{t}", 4)
        s.bouguer.spectral = "full"
        full = transmittance(s, slab, "BOUGUER", f"absorb-full-{t}", 4)
        print(f"  t = {t}: exp(-density (1 - colour) t) = {np.round(expected, 4)}, Cycles {np.round(cycles, 4)}, "
              f"Bouguer rgb3 {np.round(ours, 4)}, full {np.round(full, 4)} ({np.round(100 * (full / expected - 1), 1)} %)")
        assert np.all(np.abs(cycles / expected - 1) < 0.01), "Cycles is not the closed form: the setup is wrong"
        assert np.all(np.abs(ours / expected - 1) < 0.01), f"rgb3 {ours} against {expected}"


def test_volume_absorption_in_centimetres():
    # With 1 BU = 1 cm the density is per centimetre (Cycles ignores the unit; the add-on divides by it).
    colour, density, t = (0.8, 0.5, 0.2), 2.0, 0.5
    expected = np.exp(-density * (1 - np.array(colour)) * t)
    s, slab = backlit_slab(lambda: volume_absorption(colour, density), t, unit_scale=0.01)
    ours = transmittance(s, slab, "BOUGUER", "absorb-cm", 4)
    assert np.all(np.abs(ours / expected - 1) < 0.01), f"rgb3 {ours} against {expected}"


def principled_volume(colour, absorption, density):
    return common.material("smoke", "ShaderNodeVolumePrincipled", "Volume", Color=(*colour, 1.0),
                           **{"Absorption Color": (*absorption, 1.0)}, Density=density)


def test_principled_volume_absorption_is_cycles():
    # A black colour scatters nothing, so the slab only absorbs: sigma_a = density (1 - sqrt(absorption
    # colour)) per channel, as Cycles computes it. 1 % catches the square root left out (6-20 % here).
    absorption, density, t = (0.6, 0.3, 0.1), 1.5, 0.5
    s, slab = backlit_slab(lambda: principled_volume((0, 0, 0), absorption, density), t)
    cycles = transmittance(s, slab, "CYCLES", "principled-volume", 16)
    ours = transmittance(s, slab, "BOUGUER", "principled-volume", 4)
    print(f"  Principled Volume: Cycles {np.round(cycles, 4)}, Bouguer {np.round(ours, 4)}")
    assert np.all(np.abs(ours / cycles - 1) < 0.01), f"{ours} against Cycles' {cycles}"


def test_principled_bsdf_takes_the_pbr_role():
    # The pbr role: one mapping with the glTF reader (scene/pbr_material.h). A module without it would
    # render Principled's base colour as diffuse; this build has it, so its absence is a failure.
    from bouguer_blender.export import export_scene, pbr_supported
    assert pbr_supported(bouguer), "the module refuses the 'pbr' role"
    s = common.new_scene()
    m = common.material("painted", "ShaderNodeBsdfPrincipled", Metallic=0.25, Roughness=0.4, IOR=1.45,
                        **{"Base Color": (0.6, 0.2, 0.1, 1)})
    common.add_mesh("plane", m, size=4)
    common.add_camera(s, (0, 0, 2), kind="ORTHO", ortho_scale=1.0)
    role = export_scene(bpy.context.evaluated_depsgraph_get(), bouguer, s.bouguer).scene["objects"][0]["pbr"]
    assert role["metallic"] == 0.25 and abs(role["roughness"] - 0.4) < 1e-6 and role["transmission"] == 0.0
    assert np.allclose(role["base_color"], (0.6, 0.2, 0.1))
    bg = s.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value, bg.inputs["Strength"].default_value = (1, 1, 1, 1), 1.0
    s.bouguer.spectral = "hero"
    ours, _ = common.render(s, "BOUGUER", "pbr", 64)
    cycles, _ = common.render(s, "CYCLES", "pbr-cycles", 64)
    ratio = ours.mean(axis=(0, 1)) / cycles.mean(axis=(0, 1))
    print(f"  Principled (metallic 0.25, roughness 0.4) under a white sky: Bouguer/Cycles {np.round(ratio, 3)}")
    # Two models of one material (glTF's against Cycles' Principled): alike, not equal; 10 % catches a
    # lost base colour or metallic (the base colour alone moves green by a factor of 3).
    assert np.all(np.abs(ratio - 1) < 0.1)


def test_principled_cases_that_are_not_glass_load_with_a_report():
    # Principled BSDFs that would have stopped the render or turned into clear glass (a second reading
    # of the add-on): glowing glass is an emitter (no medium inside an emitter), a little transmission
    # or a transmitting metal stay opaque as Cycles weights them, and a Glass IOR below 1 (Cycles' air
    # bubble) is clamped to 1. Each loads through load_dict and says what it changed.
    from bouguer_blender.export import export_scene
    cases = {
        "glowing-glass": dict(Transmission=1.0, Emission=(1, 0.5, 0.2, 1), **{"Emission Strength": 2.0}),
        "hazy": dict(Transmission=0.1, Metallic=0.0),
        "metal-glass": dict(Transmission=1.0, Metallic=1.0),
    }
    for name, inputs in cases.items():
        s = common.new_scene()
        common.add_mesh("cube", common.material(name, "ShaderNodeBsdfPrincipled", **inputs), size=1)
        common.add_camera(s, (0, 0, 4), kind="ORTHO", ortho_scale=3.0)
        out = export_scene(bpy.context.evaluated_depsgraph_get(), bouguer, s.bouguer)
        obj = out.scene["objects"][0]
        assert "inside" not in obj and "pbr" in obj, (name, obj.keys())
        if name == "glowing-glass":
            assert obj["pbr"]["emission_strength"] == 2.0
        else:
            assert any("transmission" in w for w in out.reports.warnings), (name, out.reports.warnings)
        bouguer.load_dict(out.scene, meshes=out.meshes)  # the scene loads: the render would not stop
    s = common.new_scene()
    common.add_mesh("cube", common.material("bubble", "ShaderNodeBsdfGlass", IOR=0.75), size=1)
    common.add_camera(s, (0, 0, 4), kind="ORTHO", ortho_scale=3.0)
    out = export_scene(bpy.context.evaluated_depsgraph_get(), bouguer, s.bouguer)
    assert out.scene["media"]["bubble"]["ior"] == 1.0 and any("IOR 0.75" in w for w in out.reports.warnings)
    bouguer.load_dict(out.scene, meshes=out.meshes)


def clear_slab(kind):
    if kind == "principled":
        # Blender's default base colour, 0.8: Cycles tints each pass through the surface by it.
        return common.material("principled-glass", "ShaderNodeBsdfPrincipled", Transmission=1.0, Roughness=0.0,
                               IOR=1.5)
    return common.material("glass", "ShaderNodeBsdfGlass", Roughness=0.0, IOR=1.5, Color=(1, 1, 1, 1))


def test_clear_slab_is_physics_for_principled_and_glass():
    # Tolerance 1 % around (1 - R)/(1 + R) = 0.923 (R = 0.04): it catches a slab that loses its second
    # surface's reflections (0.92 -> 0.96 with one surface) or Cycles' Principled tint (0.587 = 0.8^2 x
    # 0.918). 1024 samples per pixel of 64 pixels: a path goes through or is reflected, so the estimate
    # is binomial, its spread sqrt(0.077 x 0.923 / 65536) = 0.1 %.
    r = ((1.5 - 1) / (1.5 + 1)) ** 2
    expected = (1 - r) / (1 + r)
    for kind in ("principled", "glass"):
        s, slab = backlit_slab(lambda: clear_slab(kind), 0.2)
        cycles = transmittance(s, slab, "CYCLES", f"clear-{kind}", 256)
        ours = transmittance(s, slab, "BOUGUER", f"clear-{kind}", 1024)
        print(f"  {kind}: closed form {expected:.4f}, Cycles {np.round(cycles, 4)}, Bouguer {np.round(ours, 4)}")
        assert np.all(np.abs(ours / expected - 1) < 0.01), f"{kind}: {ours} against {expected}"


def library_slab(name, t, ior=None, concentration=None):
    """A slab of a library medium, its Bouguer transmittance, and the closed form
    (1 - R)^2 tau / (1 - R^2 tau^2), tau = exp(-sigma_a t) at the rgb3 lines."""
    def make():
        m = bpy.data.materials.new(name)
        m.bouguer.source, m.bouguer.library = "LIBRARY", name
        if ior is not None:
            m.bouguer.ior_source, m.bouguer.ior = "NUMBER", ior
        if concentration is not None:
            m.bouguer.concentration = concentration
        return m

    s, slab = backlit_slab(make, t)
    ours = transmittance(s, slab, "BOUGUER", name, 1024)
    medium = bouguer.material(name, **({"concentration": concentration} if concentration else {}))
    n = ior if ior is not None else medium.ior
    r = ((n - 1) / (n + 1)) ** 2
    tau = np.exp(-medium.sigma_a_per_m(RGB3_NM) * t)
    expected = (1 - r) ** 2 * tau / (1 - r * r * tau * tau)
    print(f"  {name} {t * 1e3:g} mm (n = {n}): closed form {np.round(expected, 4)}, Bouguer {np.round(ours, 4)}")
    assert np.all(np.abs(ours / expected - 1) < 0.01), f"{ours} against {expected}"


def test_library_glass_slab_is_its_closed_form():
    # 1 % catches a concentration, a thickness or a unit off by 1 % of the optical depth near 1, or the
    # library's own index lost (1.52 against the interface's 1.5 is 0.3 % in R: not caught; the
    # solute's index given is).
    library_slab("pale-blue-glass", 0.003)                   # the entry's own index
    library_slab("copper-sulfate", 0.01, ior=1.333, concentration=0.05)  # a solute in mol/L


# ---- a small scene of Diffuse BSDF surfaces under a point light, a sun, an area light and the world ----

def diffuse_scene():
    s = common.new_scene((48, 32))
    w = s.world.node_tree.nodes["Background"]
    w.inputs["Color"].default_value, w.inputs["Strength"].default_value = (0.2, 0.3, 0.5, 1), 0.6
    common.add_mesh("plane", common.diffuse("floor", (0.6, 0.55, 0.5)), size=8)
    common.add_mesh("cube", common.diffuse("red", (0.7, 0.15, 0.1)), size=1.0, location=(-0.6, 0.2, 0.5),
                    rotation=(0, 0, 0.5))
    common.add_mesh("uv_sphere", common.diffuse("teal", (0.1, 0.5, 0.6)), radius=0.5, location=(0.8, -0.2, 0.5),
                    segments=48, ring_count=24)
    bpy.ops.object.shade_smooth()
    common.add_light(s, "POINT", location=(1.5, -1.0, 2.0), energy=300, shadow_soft_size=0)
    common.add_light(s, "SUN", rotation=(math.radians(40), 0, math.radians(-30)), energy=1.5, angle=0)
    common.add_light(s, "AREA", location=(-1.0, 1.5, 3.5), rotation=(math.radians(20), 0, 0), energy=400, size=1.0)
    common.add_camera(s, (0.3, -5.0, 2.6), (math.radians(68), 0, 0), kind="PERSP", lens=35.0)
    return s


def test_image_texture_on_uvs_is_cycles():
    # A diffuse plane with an Image Texture (an 8-bit sRGB PNG whose colour runs with u and v) under a
    # white world, seen from above: any flip of u or v, or a missing sRGB decoding, moves pixels by 0.1
    # or more; both renderers filter bilinearly, so 0.01 on average is their agreement.
    s = common.new_scene((24, 24))
    w, h = 16, 16
    u, v = np.meshgrid((np.arange(w) + 0.5) / w, (np.arange(h) + 0.5) / h)
    rgba = np.stack([u, v, 0.3 + 0.5 * u * v, np.ones_like(u)], axis=-1).astype(np.float32)
    image = bpy.data.images.new("label", w, h)
    image.pixels.foreach_set(rgba.ravel())
    image.filepath_raw = str(common.OUT / "label.png")
    image.file_format = "PNG"
    image.save()
    m = common.diffuse("label")
    tex = m.node_tree.nodes.new("ShaderNodeTexImage")
    tex.image = bpy.data.images.load(str(common.OUT / "label.png"))
    m.node_tree.links.new(tex.outputs["Color"], m.node_tree.nodes["Diffuse BSDF"].inputs["Color"])
    common.add_mesh("plane", m, size=2, rotation=(0, 0, 0.3))
    bg = s.world.node_tree.nodes["Background"]
    bg.inputs["Color"].default_value, bg.inputs["Strength"].default_value = (1, 1, 1, 1), 1.0
    common.add_camera(s, (0, 0, 1), kind="ORTHO", ortho_scale=1.6)
    s.bouguer.spectral = "hero"  # textures are lifted per texel, not read at three lines
    cycles, _ = common.render(s, "CYCLES", "label-cycles", 64)
    ours, _ = common.render(s, "BOUGUER", "label-bouguer", 64)
    d = np.abs(cycles - ours).mean()
    print(f"  image texture: Cycles mean {np.round(cycles.mean(axis=(0, 1)), 4)}, Bouguer "
          f"{np.round(ours.mean(axis=(0, 1)), 4)}, mean difference {d:.4f}")
    assert d < 0.01


def test_diffuse_scene_within_delta_e_of_cycles():
    # Mean CIEDE2000 below 1 + the two renderers' seed-to-seed floors (the issue's criterion): the
    # floors are each renderer's own noise, so what is left is their difference. It catches any light's
    # conversion off by more than a few per cent, a reflectance lifted wrongly, a missing bounce.
    s = diffuse_scene()
    images = {}
    for engine in ("CYCLES", "BOUGUER"):
        for seed in (1, 2):
            s.cycles.seed = seed
            s.bouguer.seed = seed
            images[engine, seed], _ = common.render(s, engine, f"diffuse-{engine.lower()}-{seed}", 256)
    floor_c = bouguer.compare(images["CYCLES", 1], images["CYCLES", 2])["mean"]
    floor_b = bouguer.compare(images["BOUGUER", 1], images["BOUGUER", 2])["mean"]
    d = bouguer.compare(images["BOUGUER", 1], images["CYCLES", 1])["mean"]
    ratio = images["BOUGUER", 1].mean(axis=(0, 1)) / images["CYCLES", 1].mean(axis=(0, 1))
    print(f"  mean dE00 Bouguer-Cycles {d:.3f}; floors: Cycles {floor_c:.3f}, Bouguer {floor_b:.3f}; "
          f"mean RGB ratio {np.round(ratio, 4)}")
    assert d < 1 + floor_c + floor_b


common.Checks().run([test_volume_absorption_slab_is_cycles_per_channel_in_rgb3, test_volume_absorption_in_centimetres,
                     test_principled_volume_absorption_is_cycles, test_principled_bsdf_takes_the_pbr_role,
                     test_principled_cases_that_are_not_glass_load_with_a_report,
                     test_clear_slab_is_physics_for_principled_and_glass, test_library_glass_slab_is_its_closed_form,
                     test_image_texture_on_uvs_is_cycles,
                     test_diffuse_scene_within_delta_e_of_cycles])

"""The engine as a user meets it: Esc keeps the image so far, an untranslatable node is reported once
and rendered with its nearest constant, and a saved .blend renders headless with
`blender -b scene.blend --addons bouguer_blender -E BOUGUER -o //out_ -f 1` from an installed add-on,
and make blender-addon's zip installs with Blender's own installer."""
import os
import subprocess
import sys
import time

import bpy
import numpy as np

sys.path.insert(0, os.path.dirname(__file__))
import common  # noqa: E402

bouguer = common.setup()
from bouguer_blender import engine  # noqa: E402


def lit_scene():
    s = common.new_scene((32, 24))
    w = s.world.node_tree.nodes["Background"]
    w.inputs["Color"].default_value, w.inputs["Strength"].default_value = (1, 1, 1, 1), 1.0
    common.add_mesh("plane", common.diffuse(), size=4)
    common.add_camera(s, (0, 0, 2), kind="ORTHO", ortho_scale=1.0)
    return s


def test_esc_keeps_the_image_so_far():
    # Esc is Blender's test_break(), which the engine asks through stop_requested(): here a stub that
    # says yes after 0.3 s of a render given 20 s.
    # The render must stop within seconds, keep the samples done (not black, not raise), and say so.
    s = lit_scene()
    s.bouguer.use_time, s.bouguer.time_s = True, 20.0  # a bound on a broken stop: 20 s, not hours
    start = time.monotonic()
    original = engine.BouguerRenderEngine.stop_requested
    engine.BouguerRenderEngine.stop_requested = lambda self: time.monotonic() - start > 0.3
    try:
        s.render.engine = "BOUGUER"
        s.render.filepath = str(common.OUT / "esc.exr")
        bpy.ops.render.render(write_still=True)
    finally:
        engine.BouguerRenderEngine.stop_requested = original
    seconds = time.monotonic() - start
    image = bpy.data.images.load(s.render.filepath)
    px = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(px)
    rgb = px.reshape(-1, 4)[:, :3]
    print(f"  stopped after {seconds:.2f} s with {engine.last_stats.get('spp')} samples; mean {rgb.mean():.3f}")
    assert engine.last_stats["stopped"] and engine.last_stats["spp"] >= 1
    assert seconds < 10
    assert abs(rgb.mean() - 0.8) < 0.05, "the image so far is not the plane under the white world (0.8)"


def test_an_untranslatable_node_is_reported_once_and_rendered():
    s = lit_scene()
    m = s.objects["Plane"].active_material
    noise = m.node_tree.nodes.new("ShaderNodeTexNoise")
    noise.name = "Clouds"
    m.node_tree.links.new(noise.outputs["Color"], m.node_tree.nodes["Diffuse BSDF"].inputs["Color"])
    common.add_mesh("cube", m, size=0.3, location=(0.2, 0, 0.2))  # the same material twice: one report
    rgb, _ = common.render(s, "BOUGUER", "noise", 4)
    about = [r for r in engine.last_reports if "Clouds" in r]
    print(f"  reports: {engine.last_reports}")
    assert len(about) == 1 and "Material 'white'" in about[0], engine.last_reports
    assert abs(rgb.mean() - 0.8) < 0.05, "not rendered with the input's own colour (0.8)"


def test_a_saved_file_renders_headless_from_an_installed_add_on():
    s = lit_scene()
    s.bouguer.spp = 4
    s.render.engine = "BOUGUER"
    folder = common.OUT / "headless"
    (folder / "scripts" / "addons").mkdir(parents=True)
    os.symlink(common.SOURCE / "blender" / "bouguer_blender", folder / "scripts" / "addons" / "bouguer_blender")
    blend = folder / "scene.blend"
    bpy.ops.wm.save_as_mainfile(filepath=str(blend))
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(folder / "scripts"), BOUGUER_BUILD=str(common.BUILD))
    run = subprocess.run([bpy.app.binary_path, "-b", str(blend), "--addons", "bouguer_blender", "-E", "BOUGUER",
                          "-o", "//out_", "-F", "OPEN_EXR", "-f", "1"], env=env, capture_output=True, text=True,
                         timeout=60)
    out = folder / "out_0001.exr"
    assert run.returncode == 0 and out.exists(), run.stdout[-2000:] + run.stderr[-2000:]
    image = bpy.data.images.load(str(out))
    px = np.empty(len(image.pixels), dtype=np.float32)
    image.pixels.foreach_get(px)
    print(f"  {out.name}: mean {px.reshape(-1, 4)[:, :3].mean():.3f}")
    assert abs(px.reshape(-1, 4)[:, :3].mean() - 0.8) < 0.05


INSTALL = """
import bpy, os, sys
zip_path, build, out = sys.argv[sys.argv.index("--") + 1:]
bpy.ops.preferences.addon_install(filepath=zip_path)
bpy.ops.preferences.addon_enable(module="bouguer_blender")
bpy.context.preferences.addons["bouguer_blender"].preferences.module_path = build
s = bpy.context.scene  # Blender's default scene: a cube under a point light
s.render.engine, s.render.resolution_percentage, s.bouguer.spp = "BOUGUER", 5, 2
s.render.filepath = out
bpy.ops.render.render(write_still=True)
"""


def test_the_zip_installs_with_blenders_installer_and_renders():
    # make blender-addon's zip, installed as a user installs it (Preferences > Add-ons > Install), the
    # module folder set in its preferences; Blender's default scene then renders with Bouguer.
    folder = common.OUT / "install"
    folder.mkdir()
    subprocess.run([sys.executable, str(common.SOURCE / "scripts" / "make-blender-addon.py"),
                    str(common.SOURCE / "blender" / "bouguer_blender"), str(folder / "bouguer_blender.zip")], check=True)
    (folder / "install.py").write_text(INSTALL)
    env = dict(os.environ, BLENDER_USER_SCRIPTS=str(folder / "scripts"), BLENDER_USER_CONFIG=str(folder / "config"))
    env.pop("BOUGUER_BUILD", None)
    run = subprocess.run([bpy.app.binary_path, "-b", "--python-exit-code", "1", "--python", str(folder / "install.py"),
                          "--", str(folder / "bouguer_blender.zip"), str(common.BUILD), str(folder / "out.png")],
                         env=env, capture_output=True, text=True, timeout=60)
    assert run.returncode == 0 and (folder / "out.png").exists(), run.stdout[-2000:] + run.stderr[-2000:]
    assert (folder / "scripts" / "addons" / "bouguer_blender" / "engine.py").exists()


def test_the_spectral_exr_and_the_statistics_are_written():
    import json
    s = lit_scene()
    s.bouguer.spectral, s.bouguer.spp = "full", 2
    s.bouguer.spectral_exr = str(common.OUT / "spectra.exr")
    s.bouguer.stats_json = str(common.OUT / "stats.json")
    common.render(s, "BOUGUER", "outputs", 2)
    stats = json.loads((common.OUT / "stats.json").read_text())
    print(f"  stats: {stats}")
    assert stats["spp"] == 2 and stats["rays"] > 0 and stats["resolution"] == [32, 24] and not stats["stopped"]
    header = (common.OUT / "spectra.exr").read_bytes()[:8192]
    assert header.count(b"nm\0") == 96, "the spectral EXR has not the full mode's 96 bins"


def test_denoise_smooths_the_image_and_keeps_its_level():
    # A diffuse plane under a white world with a ball above it, at 4 samples: the plane's shade
    # about the ball is noise at 4 samples. Denoise takes most of the noise and keeps the level. A
    # property that did not reach the render leaves the noise as it was; a filter that darkened or
    # brightened moves the mean.
    s = lit_scene()
    common.add_mesh("uv_sphere", common.diffuse(), radius=0.25, location=(0, 0, 0.3))
    s.bouguer.seed = 3
    noisy, _ = common.render(s, "BOUGUER", "noisy", 4)
    s.bouguer.use_denoise = True
    denoised, _ = common.render(s, "BOUGUER", "denoised", 4)
    # The noise is the difference from the image smoothed over 5 x 5 pixels (the shade's own
    # gradient is gentle): it falls by half at least.
    def noise(image):
        grey = image.mean(axis=2)
        k = np.ones(5) / 5
        smooth = np.apply_along_axis(lambda r: np.convolve(r, k, "same"), 1, grey)
        smooth = np.apply_along_axis(lambda c: np.convolve(c, k, "same"), 0, smooth)
        return (grey - smooth)[2:-2, 2:-2].std()
    print(f"  noise {noise(noisy):.4f} noisy, {noise(denoised):.4f} denoised; "
          f"means {noisy.mean():.4f}, {denoised.mean():.4f}")
    assert noise(noisy) > 0.01, "the scene has no noise to take"
    assert noise(denoised) < noise(noisy) / 2
    assert abs(denoised.mean() - noisy.mean()) < 0.01


common.Checks().run([test_denoise_smooths_the_image_and_keeps_its_level, test_the_spectral_exr_and_the_statistics_are_written, test_the_zip_installs_with_blenders_installer_and_renders, test_esc_keeps_the_image_so_far, test_an_untranslatable_node_is_reported_once_and_rendered,
                     test_a_saved_file_renders_headless_from_an_installed_add_on])

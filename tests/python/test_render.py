"""bouguer.load / load_dict / render against the command line."""
import base64
import json
import struct
import subprocess
import warnings

import numpy as np
import pytest

import bouguer
from conftest import BINARY, read_pfm


def cli_render(scene_path, out, *args):
    subprocess.run([BINARY, "render", str(scene_path), "-o", str(out), "--quiet", *args], check=True)
    return read_pfm(out)


@pytest.mark.parametrize("integrator", ["path", "bdpt"])
def test_denoised_image_is_the_cli_denoised_image_bit_for_bit(tmp_path, small_scene, integrator):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    expected = cli_render(path, tmp_path / "cli.pfm", "--integrator", integrator, "--seed", "11", "--denoise")
    noisy = bouguer.render(bouguer.load(path), integrator=integrator, seed=11)
    image = bouguer.render(bouguer.load(path), integrator=integrator, seed=11, threads=1, denoise=True)
    np.testing.assert_array_equal(image, expected)
    assert not np.array_equal(image, noisy)  # it filtered something
    with pytest.raises(ValueError, match="denoise: the light tracer"):
        bouguer.render(bouguer.load(path), integrator="light", denoise=True)


@pytest.mark.parametrize("integrator", ["whitted", "path", "light", "bdpt"])
def test_module_image_is_the_cli_image_bit_for_bit(tmp_path, small_scene, integrator):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    expected = cli_render(path, tmp_path / "cli.pfm", "--integrator", integrator, "--seed", "11", "--threads", "2")
    image = bouguer.render(bouguer.load(path), integrator=integrator, seed=11, threads=1)
    assert image.dtype == np.float32 and image.shape == (16, 24, 3)
    assert image.max() > 0.0
    np.testing.assert_array_equal(image, expected)


def test_auto_chooses_as_the_cli_and_says_which(tmp_path, small_scene):
    # integrator "auto" (integrators/choose.h): the same trials, the same choice, the same image;
    # 32 spp so that there are trials (2 spp each).
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    stats = tmp_path / "stats.json"
    expected = cli_render(path, tmp_path / "cli.pfm", "--integrator", "auto", "--spp", "32", "--seed", "11",
                          "--stats-json", str(stats))
    scene = bouguer.load(path)
    image = bouguer.render(scene, integrator="auto", spp=32, seed=11, threads=1)
    np.testing.assert_array_equal(image, expected)
    chosen = json.loads(stats.read_text())["auto"]["chosen"]
    assert scene.stats["integrator"] == chosen
    assert chosen in ("path", "bdpt", "vcm")
    assert [t["integrator"] for t in json.loads(stats.read_text())["auto"]["trials"]] == ["path", "bdpt", "vcm"]


def test_overrides_are_the_cli_options(tmp_path, small_scene):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    expected = cli_render(path, tmp_path / "cli.pfm", "--spp", "3", "--resolution", "10x7", "--spectral", "full",
                          "--max-depth", "3")
    scene = bouguer.load(path)
    image = bouguer.render(scene, spp=3, resolution=(10, 7), spectral="full", max_depth=3)
    np.testing.assert_array_equal(image, expected)
    # The resolution is for that render only.
    assert scene.resolution == (24, 16)
    assert bouguer.render(scene, spp=1).shape == (16, 24, 3)


def test_spectra_come_with_their_wavelengths(small_scene):
    scene = bouguer.load_dict(small_scene)
    rgb, spectra, wavelengths_nm = bouguer.render(scene, spp=1, spectral="full", spectra=True)
    assert spectra.shape[:2] == rgb.shape[:2] and spectra.shape[2] == wavelengths_nm.shape[0]
    assert spectra.dtype == np.float32
    assert np.all(np.diff(wavelengths_nm) > 0) and 360 <= wavelengths_nm[0] and wavelengths_nm[-1] <= 830
    assert spectra.max() > 0.0
    np.testing.assert_array_equal(rgb, bouguer.render(scene, spp=1, spectral="full"))


def test_a_dict_equals_its_json_twin(tmp_path, small_scene):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    from_file = bouguer.render(bouguer.load(path), threads=2)
    from_dict = bouguer.render(bouguer.load_dict(small_scene), threads=1)
    np.testing.assert_array_equal(from_file, from_dict)


def test_relative_paths_in_a_dict_are_against_base(tmp_path, small_scene):
    (tmp_path / "sub").mkdir()
    (tmp_path / "sub" / "tri.obj").write_text("v -0.01 0 0\nv 0.01 0 0\nv 0 0.01 0\nf 1 2 3\n")
    small_scene["objects"].append({"name": "tri", "shape": {"type": "mesh", "file": "sub/tri.obj"},
                                   "material": {"type": "diffuse", "reflectance": 0.5}})
    scene = bouguer.load_dict(small_scene, base=tmp_path)
    assert bouguer.render(scene, spp=1).shape == (16, 24, 3)
    with pytest.raises(bouguer.Error, match="tri.obj"):
        bouguer.load_dict(small_scene, base=tmp_path / "sub")


def test_bad_dicts_raise_with_the_key_path(small_scene):
    small_scene["objects"][0]["shape"]["radius"] = "-3 mm"
    with pytest.raises(bouguer.Error, match=r"objects\[0\]\.shape\.radius") as caught:
        bouguer.load_dict(small_scene)
    assert "\n" not in str(caught.value)
    assert isinstance(caught.value, ValueError)


def test_unknown_keys_raise_with_a_suggestion(small_scene):
    small_scene["camera"]["fov_dg"] = 30
    with pytest.raises(bouguer.Error, match=r"camera.*fov_deg"):
        bouguer.load_dict(small_scene)


def test_a_bad_file_raises_the_cli_message(tmp_path, small_scene):
    small_scene["render"]["integrator"] = "pathh"
    path = tmp_path / "bad.json"
    path.write_text(json.dumps(small_scene))
    cli = subprocess.run([BINARY, "render", str(path), "-o", str(tmp_path / "x.png")], capture_output=True, text=True)
    assert cli.returncode == 1
    with pytest.raises(bouguer.Error) as caught:
        bouguer.load(path)
    assert cli.stderr.strip() == f"bouguer: error: {caught.value}"


def test_bad_render_arguments_raise(small_scene):
    scene = bouguer.load_dict(small_scene)
    with pytest.raises(bouguer.Error, match="spp"):
        bouguer.render(scene, spp=0)
    with pytest.raises(bouguer.Error, match="integrator"):
        bouguer.render(scene, integrator="nope")
    with pytest.raises(bouguer.Error, match="resolution"):
        bouguer.render(scene, resolution=(0, 5))


def test_progress_is_reported_and_an_exception_in_it_stops_the_render(small_scene):
    scene = bouguer.load_dict(small_scene)
    seen = []
    bouguer.render(scene, spp=2, progress=seen.append)
    assert seen and seen[-1] == 1.0 and seen == sorted(seen)

    def stop(_fraction):
        raise KeyboardInterrupt

    with pytest.raises(KeyboardInterrupt):
        bouguer.render(scene, spp=64, resolution=(64, 64), progress=stop)
    # The scene renders again afterwards.
    assert bouguer.render(scene, spp=1).shape == (16, 24, 3)


def test_ctrl_c_stops_the_render_cleanly(small_scene):
    import _thread
    import threading
    import time

    scene = bouguer.load_dict(small_scene)
    # Another Python thread runs during the render (the GIL is released) and interrupts it as Ctrl-C would.
    timer = threading.Timer(0.2, _thread.interrupt_main)
    start = time.monotonic()
    timer.start()
    with pytest.raises(KeyboardInterrupt):
        bouguer.render(scene, spp=1 << 20, resolution=(64, 64), threads=2)
    assert time.monotonic() - start < 10.0
    timer.join()
    assert bouguer.render(scene, spp=1).shape == (16, 24, 3)


def test_many_samples_in_passes_are_the_cli_image(tmp_path, small_scene):
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    expected = cli_render(path, tmp_path / "cli.pfm", "--spp", "300", "--resolution", "6x4", "--integrator", "light")
    image = bouguer.render(bouguer.load(path), spp=300, resolution=(6, 4), integrator="light", threads=2)
    np.testing.assert_array_equal(image, expected)


def hot_triangle_gltf(tmp_path):
    """One triangle whose material's base colour is above 1 (a .gltf with its buffer inside)."""
    positions = struct.pack("<9f", 0, 0, 0, 1, 0, 0, 0, 1, 0)
    doc = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
           "meshes": [{"primitives": [{"attributes": {"POSITION": 0}, "material": 0}]}],
           "materials": [{"name": "Hot", "pbrMetallicRoughness": {"baseColorFactor": [1.5, 0.5, 0.5, 1],
                                                                  "metallicFactor": 0}}],
           "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                          "min": [0, 0, 0], "max": [1, 1, 0]}],
           "bufferViews": [{"buffer": 0, "byteLength": 36}],
           "buffers": [{"byteLength": 36,
                        "uri": "data:application/octet-stream;base64," + base64.b64encode(positions).decode()}]}
    path = tmp_path / "hot.gltf"
    path.write_text(json.dumps(doc))
    return path


def test_clamped_gltf_values_are_user_warnings(tmp_path, small_scene):
    path = hot_triangle_gltf(tmp_path)
    expected = r"hot.gltf: materials\[0\]: material 'Hot': baseColorFactor\[0\] 1.5 as 1"
    with pytest.warns(UserWarning, match=expected) as record:
        bouguer.load(path)
    assert len(record) == 1
    small_scene["objects"].append({"gltf": str(path), "name": "hot"})
    with pytest.warns(UserWarning, match=expected):
        bouguer.load_dict(small_scene)
    with warnings.catch_warnings():  # where the filters make warnings errors, loading raises
        warnings.simplefilter("error")
        with pytest.raises(UserWarning):
            bouguer.load(path)

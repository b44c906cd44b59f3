"""What a front end living inside another tool needs (Blender's add-on, blender/): meshes handed over as
arrays, the image pass by pass, a stop that keeps the image so far, a budget of seconds, the statistics."""
import re
import time

import numpy as np
import pytest

import bouguer

# A cube (outward faces) as arrays and as the OBJ file with the same triangles; its coordinates are exact
# in float, which tinyobjloader reads, so that the two are the same numbers.
H = 1 / 128
CUBE_POSITIONS = np.array([[x, y, z] for x in (-H, H) for y in (-H, H) for z in (-H, H)])
CUBE_TRIANGLES = np.array([[0, 1, 3], [0, 3, 2], [4, 6, 7], [4, 7, 5], [0, 4, 5], [0, 5, 1],
                           [2, 3, 7], [2, 7, 6], [0, 2, 6], [0, 6, 4], [1, 5, 7], [1, 7, 3]])


def cube_scene(shape):
    return {
        "camera": {"position": [0.03, 0.04, 0.08], "look_at": [0, 0, 0], "fov_deg": 30, "resolution": [24, 16]},
        "render": {"integrator": "path", "spectral": "rgb3", "spp": 4, "seed": 2},
        "media": {"glass": {"ior": 1.5, "absorption": {"library": "red-glass"}}},
        "objects": [
            {"name": "cube", "shape": shape, "inside": "glass"},
            {"name": "floor", "shape": {"type": "quad", "size": [1, 1]}, "material": {"type": "diffuse"},
             "transform": [{"rotate_deg": [-90, [1, 0, 0]]}, {"translate": [0, -H, 0]}]},
        ],
        "background": {"spectrum": "D65", "scale": 1},
    }


def write_obj(path, positions, triangles):
    lines = [f"v {x!r} {y!r} {z!r}" for x, y, z in positions]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in triangles]
    path.write_text("\n".join(lines) + "\n")


def test_a_mesh_as_arrays_renders_as_the_same_triangles_from_a_file(tmp_path):
    write_obj(tmp_path / "cube.obj", CUBE_POSITIONS, CUBE_TRIANGLES)
    from_file = bouguer.render(bouguer.load_dict(cube_scene({"type": "mesh", "file": "cube.obj"}), base=tmp_path))
    meshes = {"cube": {"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES}}
    from_arrays = bouguer.render(bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube"}), meshes=meshes))
    np.testing.assert_array_equal(from_arrays, from_file)
    # Lists work too (anything numpy converts), and the glass is seen: the image is not the floor alone.
    as_lists = {"cube": {"positions": CUBE_POSITIONS.tolist(), "triangles": CUBE_TRIANGLES.tolist()}}
    np.testing.assert_array_equal(
        bouguer.render(bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube"}), meshes=as_lists)), from_file)


def test_normals_and_uvs_arrive_as_the_obj_files_vn_and_vt(tmp_path):
    # A quad whose shading normals lean: the diffuse floor's shading follows them, as an OBJ's `vn` does.
    positions = np.array([[-0.5, 0, -0.5], [0.5, 0, -0.5], [0.5, 0, 0.5], [-0.5, 0, 0.5]])
    triangles = np.array([[0, 2, 1], [0, 3, 2]])
    normals = np.array([[0.25, 1, 0], [0.25, 1, 0], [-0.25, 1, 0], [-0.25, 1, 0]])
    uvs = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], dtype=float)
    lines = [f"v {x} {y} {z}" for x, y, z in positions] + [f"vn {x} {y} {z}" for x, y, z in normals]
    lines += [f"vt {u} {v}" for u, v in uvs]
    lines += [f"f {a + 1}/{a + 1}/{a + 1} {b + 1}/{b + 1}/{b + 1} {c + 1}/{c + 1}/{c + 1}" for a, b, c in triangles]
    (tmp_path / "quad.obj").write_text("\n".join(lines) + "\n")

    def scene(shape):
        return {"camera": {"position": [0, 1, 0.6], "look_at": [0, 0, 0], "resolution": [16, 12]},
                "render": {"integrator": "path", "spectral": "rgb3", "spp": 2},
                "objects": [{"shape": shape, "material": {"type": "diffuse"}}],
                "lights": [{"type": "point", "position": [0.5, 0.3, 0], "spectrum": "D65", "scale": 0.1}]}

    from_file = bouguer.render(bouguer.load_dict(scene({"type": "mesh", "file": "quad.obj"}), base=tmp_path))
    meshes = {"q": {"positions": positions, "triangles": triangles, "normals": normals, "uvs": uvs}}
    np.testing.assert_array_equal(bouguer.render(bouguer.load_dict(scene({"type": "mesh", "arrays": "q"}), meshes=meshes)),
                                  from_file)
    flat = {"q": {"positions": positions, "triangles": triangles}}
    assert not np.array_equal(bouguer.render(bouguer.load_dict(scene({"type": "mesh", "arrays": "q"}), meshes=flat)),
                              from_file)


@pytest.mark.parametrize("mesh, message", [
    ({"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES + 1}, "meshes['cube'].triangles[2]: vertex 8 is not one"),
    ({"positions": np.where(CUBE_POSITIONS > 0, np.nan, CUBE_POSITIONS), "triangles": CUBE_TRIANGLES},
     "meshes['cube'].positions[1]: expected finite"),
    ({"positions": CUBE_POSITIONS[:, :2], "triangles": CUBE_TRIANGLES}, "meshes['cube'].positions: expected an array of shape (N, 3)"),
    ({"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES, "normals": CUBE_POSITIONS[:4]},
     "meshes['cube'].normals: 4 normals for 8 positions"),
    ({"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES, "normals": CUBE_POSITIONS * 0},
     "meshes['cube'].normals[0]: expected a finite, non-zero vector"),
    ({"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES, "uv": CUBE_POSITIONS}, "meshes['cube'].uv: unknown key (did you mean 'uvs'?)"),
    ({"positions": CUBE_POSITIONS, "triangles": np.zeros((0, 3), int)}, "meshes['cube'].triangles: the mesh has no triangles"),
    ({"positions": "abc", "triangles": CUBE_TRIANGLES}, "meshes['cube'].positions: expected an array of numbers"),
    ({"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES + 0.7},
     "meshes['cube'].triangles: expected whole numbers (an integer array), found dtype float64"),
])
def test_bad_mesh_arrays_name_their_place(mesh, message):
    with pytest.raises(bouguer.Error, match="<dict>: " + re.escape(message)):
        bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube"}), meshes={"cube": mesh})


def test_an_unknown_mesh_name_is_refused_with_a_suggestion(tmp_path):
    meshes = {"cube": {"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES}}
    with pytest.raises(bouguer.Error, match=r"objects\[0\].shape.arrays: no mesh 'cub' was given \(did you mean 'cube'\?\)"):
        bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cub"}), meshes=meshes)
    with pytest.raises(bouguer.Error, match="exist only in Python's load_dict"):
        bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube"}))
    with pytest.raises(bouguer.Error, match="either 'file'"):
        bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube", "file": "cube.obj"}), meshes=meshes)
    # Meshes as arrays still get every check of an interface: an open one cannot hold glass.
    open_box = {"cube": {"positions": CUBE_POSITIONS, "triangles": CUBE_TRIANGLES[:-1]}}
    with pytest.raises(bouguer.Error, match="cube"):
        bouguer.load_dict(cube_scene({"type": "mesh", "arrays": "cube"}), meshes=open_box)


def test_each_pass_hands_over_its_image_and_the_last_is_the_result(small_scene):
    scene = bouguer.load_dict(small_scene)
    seen = []

    def on_pass(rgb, done, spp):
        assert rgb.shape == (16, 24, 3) and rgb.dtype == np.float32
        seen.append((rgb.copy(), done, spp, scene.stats["spp"]))

    image = bouguer.render(scene, spp=16, on_pass=on_pass, threads=2)
    assert [s[1] for s in seen] == [1, 2, 4, 8, 16]
    assert all(s[2] == 16 and s[3] == s[1] for s in seen)
    np.testing.assert_array_equal(seen[-1][0], image)
    # The images so far are images of fewer samples, not of unfinished tiles: each is lit all over and
    # closer to the final one as samples are added.
    errors = [np.abs(s[0] - image).mean() for s in seen]
    assert all(s[0].mean() > 0.3 * image.mean() for s in seen)
    assert errors[0] > errors[2] > errors[3] > 0
    # A callback changes nothing in the image.
    np.testing.assert_array_equal(bouguer.render(scene, spp=16, threads=1), image)


def test_should_stop_keeps_the_image_so_far(small_scene):
    scene = bouguer.load_dict(small_scene)
    passes = []
    image = bouguer.render(scene, spp=1 << 20, threads=2, on_pass=lambda rgb, done, spp: passes.append(done),
                           should_stop=lambda: len(passes) >= 3)
    stats = scene.stats
    assert stats["stopped"] and stats["spp_requested"] == 1 << 20
    assert stats["spp"] >= 4 and stats["spp"] < 1 << 20
    assert np.isfinite(image).all() and image.mean() > 0.05
    # The image is that of the samples every pixel has (plus the stopped pass's finished tiles): close
    # to a render of that many samples, not dimmed by the samples asked for.
    reference = bouguer.render(scene, spp=stats["spp"], threads=2)
    assert abs(image.mean() / reference.mean() - 1) < 0.1
    assert not scene.stats["stopped"]


def test_an_exception_in_should_stop_stops_and_raises(small_scene):
    scene = bouguer.load_dict(small_scene)

    def broken():
        raise RuntimeError("from should_stop")

    with pytest.raises(RuntimeError, match="from should_stop"):
        bouguer.render(scene, spp=1 << 20, should_stop=broken)


def test_a_budget_of_seconds_ends_the_render(small_scene):
    scene = bouguer.load_dict(small_scene)
    start = time.monotonic()
    image = bouguer.render(scene, time_s=0.5, resolution=(48, 32), threads=2)
    elapsed = time.monotonic() - start
    stats = scene.stats
    # A pass that would not end within the budget is cut at the rate measured so far; the loaded
    # machine makes a pass up to about 1.4 times slower than measured (cmd_render's test), so 2x.
    assert elapsed < 1.0 + 1.0
    assert 1 <= stats["spp"] < 1 << 20 and not stats["stopped"]
    assert np.isfinite(image).all() and image.mean() > 0.05
    # with spp as well, whichever comes first
    bouguer.render(scene, time_s=30, spp=4)
    assert scene.stats["spp"] == 4
    with pytest.raises(bouguer.Error, match="time_s: must be a positive number"):
        bouguer.render(scene, time_s=0)


def test_stats_count_the_rays(small_scene):
    scene = bouguer.load_dict(small_scene)
    bouguer.render(scene, spp=8)
    stats = scene.stats
    assert stats["spp"] == 8 and stats["rays"] >= 24 * 16 * 8
    assert stats["seconds"] > 0 and stats["rays_per_second"] == pytest.approx(stats["rays"] / stats["seconds"])


@pytest.mark.parametrize("camera", [{"type": "pinhole", "fov_deg": 40}, {"type": "orthographic", "width": 0.05}])
def test_a_shifted_camera_sees_part_of_a_wider_frame(camera):
    # A 32x16 frame, and a 16x16 one shifted by half its side to the right and by a quarter up at
    # the same fov (across the shorter, vertical side): the shifted one is the frame's right half,
    # a quarter of the height up. Pixels meet other random numbers, so they agree to the noise.
    def scene(resolution, shift):
        s = {"camera": dict(camera, position=[0.01, 0.02, 0.08], look_at=[0.01, 0.02, 0], resolution=resolution,
                            shift=shift),
             "render": {"integrator": "path", "spectral": "rgb3", "spp": 64, "seed": 1},
             "objects": [{"shape": {"type": "box", "size": [0.03, 0.03, 0.03]}, "material": {"type": "diffuse"},
                          "transform": [{"translate": [0.035, 0.02, 0]}]}],
             "background": {"spectrum": "D65", "scale": 1}}
        return bouguer.load_dict(s)

    wide = bouguer.render(scene([32, 16], [0, 0]), resolution=(32, 16))
    shifted = bouguer.render(scene([16, 16], [0.5, 0]))
    # The box's silhouette (dark against the bright background) is where the wide frame has it.
    np.testing.assert_array_equal(shifted[..., 1] < 0.9, wide[:, 16:, 1] < 0.9)
    assert (shifted[..., 1] < 0.9).sum() > 40
    # Up by a quarter of the side: the window moves 4 rows up, so what it sees moves 4 rows down.
    up = bouguer.render(scene([16, 16], [0.5, 0.25]))
    np.testing.assert_array_equal(up[4:, :, 1] < 0.9, wide[:12, 16:, 1] < 0.9)
    with pytest.raises(bouguer.Error, match=r"camera.shift\[1\]: must be between -100 and 100"):
        scene([16, 16], [0, 1000])


def test_the_spectral_exr_is_the_command_lines(tmp_path, small_scene):
    import json
    import subprocess

    from conftest import BINARY
    path = tmp_path / "scene.json"
    path.write_text(json.dumps(small_scene))
    bouguer.render(bouguer.load(path), spp=2, spectral="full", spectral_exr=tmp_path / "module.exr")
    subprocess.run([BINARY, "render", str(path), "-o", str(tmp_path / "cli.pfm"), "--spp", "2", "--quiet",
                    "--spectral", "full", "--spectral-exr", str(tmp_path / "cli.exr")], check=True)
    assert (tmp_path / "module.exr").read_bytes() == (tmp_path / "cli.exr").read_bytes()


def test_reflectance_spectrum_is_the_lift_of_rgb_reflectances():
    # rgb3 reads a reflectance at its three lines: a quad of {"rgb": c} under a uniform sky, over the
    # same quad of reflectance 1, is the lift at 700.0, 546.1 and 435.8 nm (no noise: the sky is uniform).
    def quad(reflectance):
        return bouguer.load_dict({
            "camera": {"type": "orthographic", "position": [0, 0, 1], "look_at": [0, 0, 0], "width": 0.5,
                       "resolution": [4, 4]},
            "render": {"integrator": "path", "spectral": "rgb3", "spp": 4, "max_depth": 1},
            "objects": [{"shape": {"type": "quad", "size": [1, 1]},
                         "material": {"type": "diffuse", "reflectance": reflectance}}],
            "background": {"spectrum": "D65", "scale": 1}})

    c = [0.8, 0.5, 0.2]
    ratio = bouguer.render(quad({"rgb": c})).mean(axis=(0, 1)) / bouguer.render(quad(1.0)).mean(axis=(0, 1))
    lift = bouguer.reflectance_spectrum(c, [700.0, 546.1, 435.8])
    np.testing.assert_allclose(ratio, lift, rtol=1e-5)
    assert abs(lift[0] - 0.8) > 0.02  # the lift is not the RGB at the lines: Blender's add-on needs both
    assert bouguer.reflectance_spectrum(c, np.array([[500.0, 600.0]])).shape == (1, 2)
    with pytest.raises(bouguer.Error, match="wavelengths must be positive"):
        bouguer.reflectance_spectrum(c, [-1.0])


def test_light_paths_land_where_a_shifted_camera_looks():
    # Light tracing reaches the film through Camera::film_position, the inverse of generate_ray: with a
    # shift, a light-traced lit quad must land on the pixels the path tracer sees it on.
    def scene(camera_type):
        cam = {"type": camera_type, "position": [0, 0, 1], "look_at": [0, 0, 0], "resolution": [24, 16],
               "shift": [0.3, -0.2]}
        cam.update({"fov_deg": 40} if camera_type == "pinhole" else {"width": 0.6})
        return bouguer.load_dict({
            "camera": cam, "render": {"spectral": "rgb3", "seed": 4},
            "objects": [{"shape": {"type": "quad", "size": [0.25, 0.2]}, "material": {"type": "diffuse"},
                         "transform": [{"translate": [0.1, 0.05, 0]}]}],
            "lights": [{"type": "point", "position": [0, 0, 0.5], "spectrum": "D65", "scale": 0.1}]})

    for camera_type in ("pinhole", "orthographic"):
        s = scene(camera_type)
        path = bouguer.render(s, integrator="path", spp=16)[..., 1]
        light = bouguer.render(s, integrator="light", spp=64)[..., 1]
        lit = path > 0.5 * path.max()
        assert 10 < lit.sum() < lit.size - 10
        # Where the path tracer sees the quad, light tracing puts its light; nowhere else: not beyond a
        # pixel of where the path tracer saw any of it (a pixel the quad's edge barely covers may
        # have no camera sample on it, as its light paths land there).
        assert light[lit].mean() > 0.8 * path[lit].mean()
        seen = path > 0
        near = seen.copy()
        near[1:, :] |= seen[:-1, :]
        near[:-1, :] |= seen[1:, :]
        near[:, 1:] |= seen[:, :-1]
        near[:, :-1] |= seen[:, 1:]
        assert not (~near).any() or light[~near].max() == 0.0


def test_many_instances_of_a_large_mesh_are_refused_before_memory_runs_out():
    # Blender hands one object per instance, each a copy of the arrays (a SceneDesc holds its meshes
    # by value). The builder counts the copies as they are added and refuses them, in one line, once
    # twice their bytes exceed the memory this process may take: here a data limit of 1 GiB against
    # 1000 copies of a 100 000-triangle mesh (3.6 GB). Without the count the copies run into the
    # limit as a MemoryError or an abort, after gigabytes.
    import subprocess
    import sys
    import textwrap
    script = textwrap.dedent("""
        import resource, sys
        resource.setrlimit(resource.RLIMIT_DATA, (1 << 30, 1 << 30))
        import numpy as np, bouguer
        n = 100_000
        p = np.random.default_rng(1).random((n + 2, 3))
        t = np.stack([np.arange(n), np.arange(1, n + 1), np.arange(2, n + 2)], axis=1)
        objects = [{"shape": {"type": "mesh", "arrays": "m"}, "material": {"type": "diffuse"},
                    "transform": [{"translate": [i * 2.0, 0, 0]}]} for i in range(1000)]
        try:
            bouguer.load_dict({"objects": objects}, meshes={"m": {"positions": p, "triangles": t}})
        except bouguer.Error as e:
            print("REFUSED", e)
            sys.exit(0)
        print("LOADED")
        sys.exit(1)
    """)
    done = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and "REFUSED" in done.stdout, (done.stdout, done.stderr[-2000:])
    assert "memory" in done.stdout and "objects[" in done.stdout, done.stdout


def test_attenuation_spectrum_is_the_gltf_readers_lift_exact_at_the_rgb3_lines():
    # The one lift of a per-channel attenuation (scene/pbr_material.h), which Blender's volumes use:
    # over the distance, the transmittance at 700.0, 546.1 and 435.8 nm is the colour's R, G and B, and
    # sigma is not negative anywhere. A second, different lift in the add-on would not be tested here.
    colour, d = (0.8, 0.5, 0.25), 0.004
    nm, sigma = bouguer.attenuation_spectrum(colour, d)
    assert nm[0] == 360 and nm[-1] == 830 and np.all(np.diff(nm) > 0) and np.all(sigma >= 0)
    for line, c in zip((700.0, 546.1, 435.8), colour):
        assert np.isclose(np.exp(-np.interp(line, nm, sigma) * d), c, rtol=1e-9), line
    with pytest.raises(bouguer.Error, match="each channel must lie in"):
        bouguer.attenuation_spectrum((0.0, 0.5, 0.5), d)

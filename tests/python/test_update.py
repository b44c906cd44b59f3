"""Changing a scene in place: the same image as a fresh load with that value, and memory held flat."""
import resource

import numpy as np
import pytest

import bouguer


def with_concentration(scene_dict, medium, concentration):
    scene_dict["media"][medium]["absorption"]["concentration"] = concentration
    return scene_dict


@pytest.mark.parametrize("integrator", ["whitted", "path"])
def test_absorption_scale_in_place_renders_as_a_fresh_load(small_scene, integrator):
    scene = bouguer.load_dict(small_scene)
    for concentration in [0.25, 3.0, 1.0]:
        scene.set_absorption_scale("glass", concentration)
        fresh = bouguer.load_dict(with_concentration(small_scene, "glass", concentration))
        np.testing.assert_array_equal(bouguer.render(scene, integrator=integrator, spectral="full"),
                                      bouguer.render(fresh, integrator=integrator, spectral="full"))
    # The scale changes the image (the test above could not pass by doing nothing).
    scene.set_absorption_scale("glass", 4.0)
    assert not np.array_equal(bouguer.render(scene), bouguer.render(bouguer.load_dict(small_scene)))


def test_camera_in_place_renders_as_a_fresh_load(small_scene):
    scene = bouguer.load_dict(small_scene)
    scene.set_camera(position_m=[0.02, 0.05, 0.1], look_at_m=[0.01, 0, 0], fov_deg=25)
    small_scene["camera"].update({"position": [0.02, 0.05, 0.1], "look_at": [0.01, 0, 0], "fov_deg": 25})
    np.testing.assert_array_equal(bouguer.render(scene), bouguer.render(bouguer.load_dict(small_scene)))
    assert scene.camera["fov_deg"] == 25


def test_bad_updates_raise_and_leave_the_scene_as_it_was(small_scene):
    scene = bouguer.load_dict(small_scene)
    before = bouguer.render(scene)
    with pytest.raises(bouguer.Error, match="no medium 'glas'.*glass"):
        scene.set_absorption_scale("glas", 2.0)
    with pytest.raises(bouguer.Error, match="finite"):
        scene.set_absorption_scale("glass", -1.0)
    with pytest.raises(bouguer.Error, match="exceeds"):
        scene.set_absorption_scale("glass", 1e300)
    with pytest.raises(bouguer.Error, match="fov_deg"):
        scene.set_camera(fov_deg=200)
    with pytest.raises(bouguer.Error, match="coincide"):
        scene.set_camera(position_m=[0, 0, 0], look_at_m=[0, 0, 0])
    np.testing.assert_array_equal(bouguer.render(scene), before)


def peak_rss_kib():
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss


def test_a_sweep_of_100_renders_holds_memory_flat(small_scene):
    # Each render makes a 96x64 film with 96 spectral bins (the returned spectra alone are 2.4 MB,
    # the film buffer of doubles twice that): a leak of any of them per render would add over
    # 200 MB in 100 renders. Peak RSS may grow by 8 MB at most.
    scene = bouguer.load_dict(small_scene)
    kwargs = dict(spp=1, resolution=(96, 64), spectral="full", spectra=True, integrator="whitted")
    for _ in range(5):  # warm up: allocator pools, numpy, the first tables
        bouguer.render(scene, **kwargs)
    before = peak_rss_kib()
    means = []
    for i in range(100):
        scene.set_absorption_scale("glass", 0.1 + 0.05 * i)
        rgb, spectra, wavelengths_nm = bouguer.render(scene, **kwargs)
        means.append(float(rgb.mean()))
    growth_kib = peak_rss_kib() - before
    assert growth_kib < 8 * 1024, f"peak RSS grew by {growth_kib} KiB over 100 renders"
    assert means[0] > means[-1]  # more absorption, darker


def test_emission_scale_in_place_renders_as_a_fresh_load(small_scene):
    small_scene["objects"][2]["emission"] = {"spectrum": {"rgb": [1.0, 0.9, 0.8]}, "scale": 1.0}
    small_scene["background"] = {"spectrum": {"rgb": [0.2, 0.3, 0.4]}, "scale": 1.0}
    scene = bouguer.load_dict(small_scene)
    scene.set_emission_scale("light", 2.5)
    scene.set_emission_scale("background", 0.5)
    small_scene["objects"][2]["emission"]["scale"] = 2.5
    small_scene["background"]["scale"] = 0.5
    fresh = bouguer.load_dict(small_scene)
    for integrator in ["path", "light"]:  # next-event and light paths both draw lights by power
        np.testing.assert_array_equal(bouguer.render(scene, integrator=integrator),
                                      bouguer.render(fresh, integrator=integrator))
    with pytest.raises(bouguer.Error, match="no emitter 'ball'.*light"):
        scene.set_emission_scale("ball", 2.0)

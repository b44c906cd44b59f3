"""bouguer.material / color / compare."""
import json
import subprocess

import numpy as np
import pytest

import bouguer
from conftest import BINARY, SOURCE_DIR


def library_sigma_a_per_m(name):
    """The material's own data: data/materials/NAME.csv (wavelength_nm, sigma_a_per_m), linear between rows."""
    rows = [line.split(",") for line in (SOURCE_DIR / "data" / "materials" / f"{name}.csv").read_text().splitlines()
            if line and line[0].isdigit()]
    table = np.array([[float(v) for v in row[:2]] for row in rows])
    return table[:, 0], table[:, 1]


@pytest.mark.parametrize("name", ["red-glass", "light-blue-glass", "cobalt-blue-glass"])
def test_transmittance_is_the_closed_form_from_the_material_data(name):
    wavelengths_nm, sigma_a_per_m = library_sigma_a_per_m(name)
    inside = (wavelengths_nm >= 380) & (wavelengths_nm <= 780)
    wavelengths_nm, sigma_a_per_m = wavelengths_nm[inside], sigma_a_per_m[inside]
    thickness_m = np.array([[0.0], [1e-3], [5e-3], [2e-2]])  # (4, 1) against (N,): broadcast to (4, N)
    t = bouguer.material(name).transmittance(wavelengths_nm, thickness_m)
    assert t.shape == (4, wavelengths_nm.size)
    np.testing.assert_allclose(t, np.exp(-sigma_a_per_m[None, :] * thickness_m), rtol=1e-12, atol=0)
    np.testing.assert_allclose(bouguer.material(name).sigma_a_per_m(wavelengths_nm), sigma_a_per_m, rtol=1e-12)
    assert isinstance(bouguer.material(name).transmittance(550.0, 1e-3), float)


def test_bad_transmittance_arguments_raise():
    glass = bouguer.material("red-glass")
    with pytest.raises(bouguer.Error, match="thickness_m"):
        glass.transmittance(550.0, -1e-3)
    with pytest.raises(bouguer.Error, match="wavelength_nm"):
        glass.transmittance(np.nan, 1e-3)
    with pytest.raises(bouguer.Error, match="red-glas"):
        bouguer.material("red-glas")


def test_slab_colour_is_the_cli_table():
    thicknesses_m = [1e-3, 4e-3, 1.6e-2]
    slab = bouguer.material("red-glass").slab_colour(thicknesses_m)
    cli = json.loads(subprocess.run([BINARY, "material", "red-glass", "--thickness", "1mm,4mm,16mm", "--json"],
                                    check=True, capture_output=True, text=True).stdout)
    rows = cli["thicknesses"] if "thicknesses" in cli else cli["rows"]
    assert [row["spectral"]["hex"] for row in rows] == slab["spectral"]["hex"]
    np.testing.assert_allclose(slab["spectral"]["linear_srgb"], [row["spectral"]["linear_srgb"] for row in rows],
                               rtol=1e-12)
    assert slab["delta_e_rgb3"].shape == (3,)
    # Thicker is darker.
    assert np.all(np.diff(slab["spectral"]["xyz"][:, 1]) < 0)


def test_color_of_d65_is_white_and_of_values_matches_the_cli(tmp_path):
    white = bouguer.color("D65")
    np.testing.assert_allclose(white["xyz"][1], 1.0, rtol=1e-9)
    assert white["srgb_hex"].lower() == "#ffffff"
    wavelengths_nm = np.arange(380.0, 781.0, 5.0)
    values = np.exp(-((wavelengths_nm - 600.0) / 40.0) ** 2)
    csv = tmp_path / "s.csv"
    csv.write_text("wavelength_nm,value\n" + "".join(f"{w},{v!r}\n" for w, v in zip(wavelengths_nm, values)))
    cli = json.loads(subprocess.run([BINARY, "color", str(csv), "--json"], check=True, capture_output=True,
                                    text=True).stdout)
    mine = bouguer.color(values, wavelengths_nm=wavelengths_nm)
    np.testing.assert_allclose(mine["xyz"], cli["XYZ"], rtol=1e-12)
    np.testing.assert_allclose(mine["lab"], cli["lab"], rtol=1e-12)
    with pytest.raises(bouguer.Error):
        bouguer.color(values)


def test_compare_gives_a_delta_e_map():
    a = np.full((4, 5, 3), 0.5, dtype=np.float32)
    b = a.copy()
    b[1, 2] = [0.6, 0.4, 0.5]
    d = bouguer.compare(a, b)
    assert d["delta_e"].shape == (4, 5)
    assert d["delta_e"][1, 2] > 1.0 and np.count_nonzero(d["delta_e"]) == 1
    assert d["max"] == d["delta_e"][1, 2]
    # (a greener pixel of nearly the same luminance: mostly colour)
    assert 0.0 < d["mean_lightness"] < d["mean_colour"] <= d["mean"] * 1.001
    assert bouguer.compare(a, a)["max"] == 0.0
    with pytest.raises(bouguer.Error, match="size"):
        bouguer.compare(a, b[:2])

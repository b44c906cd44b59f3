// The colour and materials tools of the Python module: library materials and their transmittance
// (vectorised over numpy arrays), the slab colour by thickness (analysis/slab_colour.h), the
// colour of a spectrum, and the ΔE00 map between two images (render/compare.h).
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "bouguer/analysis/slab_colour.h"
#include "bouguer/core/error.h"
#include "bouguer/render/compare.h"
#include "bouguer/media/library.h"
#include "bouguer/scene/material_file.h"
#include "bouguer/spectra/cie.h"
#include "bouguer/spectra/cielab.h"
#include "bouguer/spectra/color_space.h"
#include "python/module.h"

namespace py = pybind11;

namespace bouguer::python {
namespace {

double checked_wavelength_nm(double wavelength_nm) {
  if (!std::isfinite(wavelength_nm) || wavelength_nm <= 0.0)
    fail("wavelength_nm: must be a positive finite number of nanometres (got {})", wavelength_nm);
  return wavelength_nm;
}

double checked_thickness_m(double thickness_m) {
  if (!std::isfinite(thickness_m) || thickness_m < 0.0)
    fail("thickness_m: must be a finite length of 0 or more metres (got {})", thickness_m);
  return thickness_m;
}

py::array_t<double> vec3_rows(const std::vector<Vec3>& v) {
  py::array_t<double> out({static_cast<py::ssize_t>(v.size()), py::ssize_t{3}});
  auto o = out.mutable_unchecked<2>();
  for (std::size_t i = 0; i < v.size(); ++i) {
    const auto r = static_cast<py::ssize_t>(i);
    o(r, 0) = v[i].x, o(r, 1) = v[i].y, o(r, 2) = v[i].z;
  }
  return out;
}

py::dict colours_dict(const std::vector<SlabColour>& c) {
  std::vector<Vec3> xyz, rgb;
  std::vector<std::string> hex;
  for (const SlabColour& s : c) xyz.push_back(s.xyz), rgb.push_back(s.linear_srgb), hex.push_back(s.hex);
  py::dict d;
  d["xyz"] = vec3_rows(xyz);
  d["linear_srgb"] = vec3_rows(rgb);
  d["hex"] = hex;
  return d;
}

// The slab of `m` at each thickness against an illuminant: the spectral colour, the two RGB
// shortcuts and their ΔE00 (what `bouguer material NAME --thickness ...` prints).
py::dict slab_colour(const ResolvedMaterial& m, const std::vector<double>& thicknesses_m, const std::string& illuminant,
                     std::optional<double> reference_thickness_m) {
  if (thicknesses_m.empty()) fail("thicknesses_m: give at least one thickness");
  for (double t : thicknesses_m)
    if (!(checked_thickness_m(t) > 0.0)) fail("thicknesses_m: each must be a positive length (got {})", t);
  const double reference = reference_thickness_m ? *reference_thickness_m : thicknesses_m[thicknesses_m.size() / 2];
  if (!(reference > 0.0) || !std::isfinite(reference))
    fail("reference_thickness_m: must be a positive length (got {})", reference);
  const ThicknessAnalysis a =
      analyse_thicknesses(m.sigma_a_per_m, m.ior, thicknesses_m, named_illuminant(illuminant, 1.0), reference);
  std::vector<SlabColour> spectral, rgb3, fitted;
  std::vector<double> de_rgb3, de_fitted;
  py::array_t<double> internal({static_cast<py::ssize_t>(a.rows.size()), static_cast<py::ssize_t>(a.probe_nm.size())});
  auto t = internal.mutable_unchecked<2>();
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    const ThicknessRow& row = a.rows[i];
    spectral.push_back(row.spectral), rgb3.push_back(row.rgb3), fitted.push_back(row.fitted);
    de_rgb3.push_back(row.delta_e_rgb3), de_fitted.push_back(row.delta_e_fitted);
    for (std::size_t j = 0; j < a.probe_nm.size(); ++j)
      t(static_cast<py::ssize_t>(i), static_cast<py::ssize_t>(j)) = row.internal_transmittance[j];
  }
  py::dict d;
  d["thickness_m"] = py::array_t<double>(static_cast<py::ssize_t>(thicknesses_m.size()), thicknesses_m.data());
  d["probe_nm"] = a.probe_nm;
  d["internal_transmittance"] = internal;
  d["ior"] = a.ior;
  d["surface_reflectance"] = a.reflectance;
  d["reference_thickness_m"] = a.reference_thickness_m;
  d["spectral"] = colours_dict(spectral);
  d["rgb3"] = colours_dict(rgb3);
  d["fitted"] = colours_dict(fitted);
  d["delta_e_rgb3"] = py::array_t<double>(static_cast<py::ssize_t>(de_rgb3.size()), de_rgb3.data());
  d["delta_e_fitted"] = py::array_t<double>(static_cast<py::ssize_t>(de_fitted.size()), de_fitted.data());
  return d;
}

// A named illuminant (normalised to Y = 1, as `bouguer color NAME`) or values at wavelengths.
Spectrum spectrum_from(const py::object& spectrum, const std::optional<std::vector<double>>& wavelengths_nm) {
  if (py::isinstance<py::str>(spectrum)) {
    const std::string name = spectrum.cast<std::string>();
    if (const auto spd = named_illuminant_spd(name)) return normalised_to_luminance(*spd, 1.0);
    fail("'{}' is not a named illuminant (D65, D50, A, E, F2, F7, F11, blackbody:<kelvin>)", name);
  }
  if (!wavelengths_nm) fail("spectrum: values need wavelengths_nm (or give an illuminant's name)");
  return make_tabulated(*wavelengths_nm, spectrum.cast<std::vector<double>>(), "spectrum");
}

py::dict color(const py::object& spectrum, const std::optional<std::vector<double>>& wavelengths_nm,
               const std::string& observer_text) {
  if (observer_text != "1931" && observer_text != "1964") fail("observer: '1931' or '1964' (got '{}')", observer_text);
  const Observer observer = observer_text == "1964" ? Observer::cie1964_10deg : Observer::cie1931_2deg;
  const Spectrum s = spectrum_from(spectrum, wavelengths_nm);
  const Vec3 xyz = spectrum_to_xyz(s, observer);
  const double sum = xyz.x + xyz.y + xyz.z;
  // RGB spaces are defined on CIE 1931 XYZ, whatever observer XYZ and Lab are asked for.
  const Vec3 rgb = xyz_to_linear_rgb(kRec709, spectrum_to_xyz(s, Observer::cie1931_2deg));
  const Lab lab = xyz_to_lab(xyz, spectrum_to_xyz(named_illuminant("D65"), observer));
  py::dict d;
  d["xyz"] = std::vector<double>{xyz.x, xyz.y, xyz.z};
  d["xy"] = std::vector<double>{sum > 0.0 ? xyz.x / sum : 0.0, sum > 0.0 ? xyz.y / sum : 0.0};
  d["linear_srgb"] = std::vector<double>{rgb.x, rgb.y, rgb.z};
  d["srgb_hex"] = srgb_hex(rgb);
  d["lab"] = std::vector<double>{lab.L, lab.a, lab.b};
  return d;
}

Film film_from(const py::array_t<float, py::array::c_style | py::array::forcecast>& image, const char* name) {
  if (image.ndim() != 3 || image.shape(2) != 3 || image.shape(0) < 1 || image.shape(1) < 1)
    fail("{}: expected an (H, W, 3) array of linear Rec.709 (got {} dimensions)", name, image.ndim());
  Film f(static_cast<int>(image.shape(1)), static_cast<int>(image.shape(0)));
  std::copy(image.data(), image.data() + image.size(), f.rgb.begin());
  return f;
}

py::dict compare(const py::array_t<float, py::array::c_style | py::array::forcecast>& a,
                 const py::array_t<float, py::array::c_style | py::array::forcecast>& b) {
  const Film fa = film_from(a, "a"), fb = film_from(b, "b");
  if (fa.width != fb.width || fa.height != fb.height)
    fail("compare: the images differ in size ({}x{} and {}x{})", fa.width, fa.height, fb.width, fb.height);
  const ImageDifference d = compare_images(fa, fb);
  py::array_t<double> map({static_cast<py::ssize_t>(d.height), static_cast<py::ssize_t>(d.width)});
  std::copy(d.delta_e.begin(), d.delta_e.end(), map.mutable_data());
  py::dict out;
  out["delta_e"] = map;
  out["mean"] = d.mean, out["median"] = d.median, out["p95"] = d.p95, out["max"] = d.max, out["rmse"] = d.rmse;
  out["mean_lightness"] = d.mean_lightness, out["mean_colour"] = d.mean_colour;
  return out;
}

}  // namespace

void register_tools(py::module_& m) {
  py::class_<ResolvedMaterial>(m, "Material", "An absorbing material: a library name or a material CSV file")
      .def_readonly("name", &ResolvedMaterial::name)
      .def_readonly("ior", &ResolvedMaterial::ior)
      .def_readonly("molar", &ResolvedMaterial::molar)
      .def_readonly("concentration", &ResolvedMaterial::concentration)
      .def(
          "sigma_a_per_m",
          [](const ResolvedMaterial& r, py::array_t<double> wavelength_nm) {
            return py::vectorize([&r](double nm) { return eval(r.sigma_a_per_m, checked_wavelength_nm(nm)); })(
                wavelength_nm);
          },
          py::arg("wavelength_nm"), "σ_a (natural log, per metre) at each wavelength")
      .def(
          "transmittance",
          [](const ResolvedMaterial& r, py::array_t<double> wavelength_nm, py::array_t<double> thickness_m) {
            return py::vectorize([&r](double nm, double d) {
              return std::exp(-eval(r.sigma_a_per_m, checked_wavelength_nm(nm)) * checked_thickness_m(d));
            })(wavelength_nm, thickness_m);
          },
          py::arg("wavelength_nm"), py::arg("thickness_m"),
          "Internal transmittance exp(-σ_a·d), broadcast over the two arrays (no surface reflections)")
      .def("slab_colour", &slab_colour, py::arg("thicknesses_m"), py::arg("illuminant") = "D65",
           py::arg("reference_thickness_m") = py::none(),
           "The colour of a slab in air at each thickness, spectral and by the two RGB shortcuts, with their ΔE00")
      .def("__repr__", [](const ResolvedMaterial& r) { return fmt::format("<bouguer.Material {}>", r.name); });
  m.def(
      "material",
      [](const std::string& name, std::optional<double> concentration) { return resolve_material(name, concentration); },
      py::arg("name"), py::arg("concentration") = py::none(),
      "A library material (bouguer material list) or a material CSV file; molar ones need concentration in mol/L");
  m.def("material_names", &library_material_names, "The names of the material library (bouguer material list)");
  m.def("color", &color, py::arg("spectrum"), py::arg("wavelengths_nm") = py::none(), py::arg("observer") = "1931",
        "XYZ, xy, linear Rec.709, sRGB hex and CIELAB (white D65, Y = 1) of an illuminant's name or of values at "
        "wavelengths_nm");
  m.def("compare", &compare, py::arg("a"), py::arg("b"),
        "CIEDE2000 between two (H, W, 3) linear Rec.709 images: the (H, W) map and its statistics");
}

}  // namespace bouguer::python

// The Python module `bouguer` (pybind11): scenes from a file or a dict with the JSON schema,
// rendered by the library path the command line takes (render/render.h) into numpy arrays.
// Errors are bouguer.Error (a ValueError) carrying the one-line message the command line prints.
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <tuple>
#include <utility>
#include <vector>

#include "bouguer/core/error.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/update.h"
#include "python/module.h"

namespace py = pybind11;
namespace fs = std::filesystem;

namespace bouguer::python {
namespace {

std::shared_ptr<Scene> scene_from(SceneDesc desc) {
  for (const std::string& w : desc.warnings)  // each a UserWarning (raised where the warning filters say "error")
    if (PyErr_WarnEx(PyExc_UserWarning, w.c_str(), 1) < 0) throw py::error_already_set();
  auto scene = std::make_shared<Scene>();
  scene->desc = std::move(desc);
  {
    const py::gil_scoped_release release;  // compiling a large mesh takes a while
    scene->compiled = std::make_unique<RenderScene>(compile(scene->desc));
  }
  return scene;
}

std::shared_ptr<Scene> load(const fs::path& path) { return scene_from(load_scene(path)); }

// The dict goes through Python's json module, so it is read by the same loader as a file: the
// same keys, checks and messages. Relative paths in it are against `base` (the working directory
// when not given); messages name it as "<dict>" in that folder.
std::shared_ptr<Scene> load_dict(const py::dict& d, const std::optional<fs::path>& base) {
  const std::string text = py::module_::import("json").attr("dumps")(d, py::arg("allow_nan") = false).cast<std::string>();
  const fs::path folder = base ? fs::absolute(*base) : fs::current_path();
  return scene_from(parse_scene(text, folder / "<dict>"));
}

struct RenderArgs {
  std::optional<std::int64_t> spp, seed, max_depth;
  std::optional<std::string> integrator, spectral;
  std::optional<std::pair<std::int64_t, std::int64_t>> resolution;
  int threads = 0;
  bool spectra = false;
  py::object progress;
};

// The scene's settings with the keyword arguments over them, each checked by the SceneBuilder's
// one check of that setting (a scratch builder: the messages name the argument).
RenderSettings settings_with(const Scene& scene, const RenderArgs& a, CameraDesc& camera) {
  RenderSettings s = scene.desc.render;
  SceneBuilder check(scene.desc.file);
  if (a.integrator) {
    check.integrator(*a.integrator, Source::option("integrator"));
    s.integrator = find_integrator(*a.integrator)->type;
  }
  if (a.spectral) {
    check.spectral_mode(*a.spectral, Source::option("spectral"));
    s.spectral = find_spectral_mode(*a.spectral)->mode;
  }
  if (a.spp) check.spp(*a.spp, Source::option("spp")), s.spp = static_cast<int>(*a.spp);
  if (a.max_depth) check.max_depth(*a.max_depth, Source::option("max_depth")), s.max_depth = static_cast<int>(*a.max_depth);
  if (a.seed) check.seed(*a.seed, Source::option("seed")), s.seed = static_cast<std::uint64_t>(*a.seed);
  if (a.resolution) {
    check.resolution(a.resolution->first, a.resolution->second, Source::option("resolution"));
    camera.width_px = static_cast<int>(a.resolution->first);
    camera.height_px = static_cast<int>(a.resolution->second);
  }
  return s;
}

// The render runs on a worker thread without the GIL; the calling thread waits for it, and every
// few tens of milliseconds takes the GIL to look for a signal (Ctrl-C: KeyboardInterrupt) and to
// call the progress callback, so Python code runs on one thread only. An interrupt sets the
// renderer's cancel flag: the tiles in flight finish, the rest are skipped, and the exception is
// raised once the worker has stopped.
void render_waiting(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, const RenderArgs& a,
                    RenderStats& stats) {
  std::atomic<bool> cancel{false};
  std::atomic<double> fraction{0.0};
  std::mutex mutex;
  std::condition_variable done_cv;
  bool done = false;
  std::exception_ptr failure;
  RenderControl control;
  control.threads = a.threads;
  control.cancel = &cancel;
  std::thread worker;
  {
    const py::gil_scoped_release release;
    worker = std::thread([&] {
      try {
        // In passes of sample ranges (any split gives the same image, render/film.h), so that an
        // interrupt waits for the tiles of one pass at most: 1, 1, 2, 4, ... up to kMaxPassSpp.
        constexpr int kMaxPassSpp = 64;
        const int spp = settings.spp;
        for (int begin = 0; begin < spp && !cancel;) {
          const int end = std::min(spp, begin + std::clamp(begin, 1, kMaxPassSpp));
          control.progress = [&, begin, end](double f) { fraction.store((begin + f * (end - begin)) / spp); };
          render_into(scene, settings, film, PixelRegion::whole(scene.camera), {begin, end}, control, stats);
          begin = end;
        }
      } catch (...) {
        failure = std::current_exception();
      }
      const std::lock_guard lock(mutex);
      done = true;
      done_cv.notify_all();
    });
  }
  double reported = -1.0;
  bool interrupted = false;
  std::optional<py::error_already_set> callback_error;
  for (;;) {
    bool finished = false;
    {
      const py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      finished = done_cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return done; });
    }
    if (!interrupted && PyErr_CheckSignals() != 0) interrupted = true, cancel = true;
    if (!interrupted && !a.progress.is_none()) {
      const double f = finished ? 1.0 : fraction.load();
      if (f != reported) {
        reported = f;
        try {
          a.progress(f);
        } catch (py::error_already_set& e) {  // an exception in the callback stops the render too
          callback_error.emplace(std::move(e));
          interrupted = true, cancel = true;
        }
      }
    }
    if (finished) break;
  }
  {
    const py::gil_scoped_release release;
    worker.join();
  }
  if (callback_error) throw std::move(*callback_error);
  if (interrupted) throw py::error_already_set();  // the KeyboardInterrupt PyErr_CheckSignals set
  if (failure) std::rethrow_exception(failure);
}

py::object render(Scene& scene, const RenderArgs& a) {
  CameraDesc camera = scene.compiled->camera;
  const RenderSettings settings = settings_with(scene, a, camera);
  // The resolution is the camera's alone: it is set for this render and put back after.
  struct CameraRestore {
    RenderScene& s;
    CameraDesc saved;
    ~CameraRestore() { s.camera = saved; }
  } restore{*scene.compiled, scene.compiled->camera};
  scene.compiled->camera = camera;
  const RenderScene& compiled = *scene.compiled;
  check_settings(compiled, settings, a.spectra);
  FilmBuffer buffer = make_film(compiled, settings, a.spectra);
  RenderStats stats;
  render_waiting(compiled, settings, buffer, a, stats);
  // Light paths splat anywhere: their scale is the light paths traced per pixel (as the CLI).
  const Film film = buffer.resolve(1.0 / settings.spp);
  if (const NonFinitePixels bad = find_non_finite(film); bad.count > 0)
    fail("{}: {} of {} pixels came out not finite (the first at ({}, {}))", scene.desc.file.string(), bad.count,
         static_cast<std::size_t>(film.width) * static_cast<std::size_t>(film.height), bad.first_x, bad.first_y);
  if (buffer.saturated_splats() > 0)
    PyErr_WarnEx(PyExc_RuntimeWarning,
                 fmt::format("{} light-path splats were not finite or beyond the film's range and were dropped",
                             buffer.saturated_splats())
                     .c_str(),
                 1);
  const auto h = static_cast<py::ssize_t>(film.height), w = static_cast<py::ssize_t>(film.width);
  py::array_t<float> rgb({h, w, py::ssize_t{3}});
  std::copy(film.rgb.begin(), film.rgb.end(), rgb.mutable_data());
  if (!a.spectra) return rgb;
  const auto n = static_cast<py::ssize_t>(film.wavelengths_nm.size());
  py::array_t<float> spectral({h, w, n});
  std::copy(film.spectral.begin(), film.spectral.end(), spectral.mutable_data());
  py::array_t<double> wavelengths_nm(n);
  std::copy(film.wavelengths_nm.begin(), film.wavelengths_nm.end(), wavelengths_nm.mutable_data());
  return py::make_tuple(rgb, spectral, wavelengths_nm);
}

}  // namespace
}  // namespace bouguer::python

PYBIND11_MODULE(bouguer, m) {
  using namespace bouguer::python;
  m.doc() = "Bouguer: a spectral renderer for transparent, absorbing and scattering matter (docs/python.md)";
  py::register_exception<bouguer::Error>(m, "Error", PyExc_ValueError);

  py::class_<Scene, std::shared_ptr<Scene>>(m, "Scene", "A loaded and compiled scene")
      .def_property_readonly("file", [](const Scene& s) { return s.desc.file; })
      .def_property_readonly("resolution",
                             [](const Scene& s) { return std::make_pair(s.compiled->camera.width_px, s.compiled->camera.height_px); })
      .def_property_readonly("spp", [](const Scene& s) { return s.desc.render.spp; })
      .def_property_readonly("seed", [](const Scene& s) { return s.desc.render.seed; })
      .def_property_readonly("integrator", [](const Scene& s) { return std::string(bouguer::integrator_info(s.desc.render.integrator).name); })
      .def_property_readonly("spectral", [](const Scene& s) { return std::string(bouguer::spectral_mode_name(s.desc.render.spectral)); })
      .def_property_readonly("media",
                             [](const Scene& s) {
                               std::vector<std::string> names;
                               for (const auto& [name, medium] : s.desc.media) names.push_back(name);
                               return names;
                             })
      .def(
          "set_absorption_scale",
          [](Scene& s, const std::string& medium, double factor) {
            bouguer::set_absorption_scale(*s.compiled, s.desc, medium, factor,
                                          bouguer::Source::option("set_absorption_scale"));
          },
          py::arg("medium"), py::arg("factor"),
          "Multiply a medium's absorption by factor against the scene as loaded (a concentration sweep: σ_a is "
          "linear in concentration); only its spectra change, nothing is compiled again")
      .def(
          "set_emission_scale",
          [](Scene& s, const std::string& object, double factor) {
            bouguer::set_emission_scale(*s.compiled, s.desc, object, factor,
                                        bouguer::Source::option("set_emission_scale"));
          },
          py::arg("object"), py::arg("factor"),
          "Multiply the emission of an emitter object (or \"background\") by factor against the scene as loaded; "
          "the light powers follow, nothing is compiled again")
      .def_property_readonly("camera",
                             [](const Scene& s) {
                               const bouguer::CameraDesc& c = s.compiled->camera;
                               py::dict d;
                               d["position_m"] = std::vector<double>{c.position_m.x, c.position_m.y, c.position_m.z};
                               d["look_at_m"] = std::vector<double>{c.look_at_m.x, c.look_at_m.y, c.look_at_m.z};
                               d["up"] = std::vector<double>{c.up.x, c.up.y, c.up.z};
                               d["fov_deg"] = c.fov_deg;
                               return d;
                             })
      .def(
          "set_camera",
          [](Scene& s, std::optional<std::array<double, 3>> position_m, std::optional<std::array<double, 3>> look_at_m,
             std::optional<std::array<double, 3>> up, std::optional<double> fov_deg) {
            bouguer::CameraDesc c = s.compiled->camera;
            auto vec = [](const std::array<double, 3>& v) { return bouguer::Vec3{v[0], v[1], v[2]}; };
            if (position_m) c.position_m = vec(*position_m);
            if (look_at_m) c.look_at_m = vec(*look_at_m);
            if (up) c.up = vec(*up);
            if (fov_deg) c.fov_deg = *fov_deg;
            bouguer::set_camera(*s.compiled, s.desc, c, bouguer::Source::option("set_camera"));
          },
          py::kw_only(), py::arg("position_m") = py::none(), py::arg("look_at_m") = py::none(),
          py::arg("up") = py::none(), py::arg("fov_deg") = py::none(),
          "Move the camera (metres, degrees) for the next renders; the geometry is not compiled again")
      .def("__repr__", [](const Scene& s) {
        return fmt::format("<bouguer.Scene {} {}x{}>", s.desc.file.string(), s.compiled->camera.width_px,
                           s.compiled->camera.height_px);
      });

  register_tools(m);
  m.def("load", &load, py::arg("path"), "Load and compile a scene file (JSON, docs/scene-format.md)");
  m.def("load_dict", &load_dict, py::arg("scene"), py::arg("base") = py::none(),
        "Load and compile a scene from a dict with the JSON schema; relative paths against `base` (default: the "
        "working directory)");
  m.def(
      "render",
      [](Scene& scene, std::optional<std::int64_t> spp, std::optional<std::string> integrator,
         std::optional<std::string> spectral, std::optional<std::int64_t> seed, int threads,
         std::optional<std::pair<std::int64_t, std::int64_t>> resolution, std::optional<std::int64_t> max_depth,
         bool spectra, py::object progress) {
        if (threads < 0 || threads > 1024) bouguer::fail_usage("threads: must be between 0 and 1024 (got {})", threads);
        RenderArgs a{spp, seed, max_depth, std::move(integrator), std::move(spectral), resolution, threads, spectra,
                     std::move(progress)};
        return render(scene, a);
      },
      py::arg("scene"), py::kw_only(), py::arg("spp") = py::none(), py::arg("integrator") = py::none(),
      py::arg("spectral") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = 0,
      py::arg("resolution") = py::none(), py::arg("max_depth") = py::none(), py::arg("spectra") = false,
      py::arg("progress") = py::none(),
      "Render: a float32 (H, W, 3) array, linear Rec.709, row 0 at the top; with spectra=True a tuple (rgb, "
      "spectra (H, W, N), wavelengths_nm (N,)). Keyword arguments override the scene's settings (the command "
      "line's names). progress(fraction) is called now and then; Ctrl-C stops the render (KeyboardInterrupt).");
}

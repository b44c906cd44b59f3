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
#include <cmath>
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
#include "bouguer/core/limits.h"
#include "bouguer/core/strings.h"
#include "bouguer/integrators/choose.h"
#include "bouguer/integrators/guiding.h"
#include "bouguer/integrators/render_into.h"
#include "bouguer/io/image_io.h"
#include "bouguer/render/denoise.h"
#include "bouguer/scene/compile.h"
#include "bouguer/scene/loader.h"
#include "bouguer/scene/pbr_material.h"
#include "bouguer/scene/update.h"
#include "bouguer/spectra/rgb_to_spectrum.h"
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
// One mesh of load_dict(meshes=...): numpy arrays (anything numpy converts) into the shape the
// loader resolves {"type": "mesh", "arrays": name} to, each count and value checked here so that
// a message names the dict's place: "<dict>: meshes['cup'].triangles[3]: ...".
template <typename T>
py::array_t<T, py::array::c_style | py::array::forcecast> rows_of(const py::handle& value, const Source& w,
                                                                   py::ssize_t columns, std::size_t max_rows) {
  py::array_t<T, py::array::c_style | py::array::forcecast> a;
  try {
    a = py::array_t<T, py::array::c_style | py::array::forcecast>::ensure(value);
  } catch (const py::error_already_set&) {
  }
  if (!a) w.fail("expected an array of numbers");
  if (a.ndim() != 2 || a.shape(1) != columns) w.fail("expected an array of shape (N, {})", columns);
  if (static_cast<std::size_t>(a.shape(0)) > max_rows) w.fail("{} rows, more than the limit of {}", a.shape(0), max_rows);
  return a;
}

TriangleMeshShape mesh_arrays(const py::dict& m, const Source& w) {
  for (const auto& [key, value] : m) {
    const std::string k = py::str(key);
    if (k != "positions" && k != "triangles" && k != "normals" && k != "uvs")
      (w / k).fail("unknown key{}", suggestion(k, {"positions", "triangles", "normals", "uvs"}));
  }
  if (!m.contains("positions") || !m.contains("triangles")) w.fail("a mesh needs 'positions' and 'triangles'");
  TriangleMeshShape s;
  const auto p = rows_of<double>(m["positions"], w / "positions", 3, kMaxMeshVertices);
  const auto n = static_cast<std::size_t>(p.shape(0));
  const auto point = [](const double* v) { return Vec3{v[0], v[1], v[2]}; };
  for (std::size_t i = 0; i < n; ++i) {
    const Vec3 v = point(p.data() + 3 * i);
    for (int c = 0; c < 3; ++c)
      if (!std::isfinite(v[c]) || std::abs(v[c]) > kMaxMeshCoordinate)
        (w / "positions")[i].fail("expected finite coordinates within ±{} m (got {})", kMaxMeshCoordinate, v[c]);
    s.mesh.positions.push_back(v);
  }
  // Indices are whole numbers: a float array (2.7) is refused rather than truncated by forcecast.
  if (const py::array given = py::array::ensure(m["triangles"]);
      given && given.dtype().kind() != 'i' && given.dtype().kind() != 'u' && given.size() > 0)
    (w / "triangles").fail("expected whole numbers (an integer array), found dtype {}", py::str(given.dtype()).cast<std::string>());
  const auto t = rows_of<std::int64_t>(m["triangles"], w / "triangles", 3, kMaxMeshTriangles);
  if (t.shape(0) == 0) (w / "triangles").fail("the mesh has no triangles");
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    std::array<std::uint32_t, 3> tri{};
    for (py::ssize_t c = 0; c < 3; ++c) {
      const std::int64_t v = t.at(i, c);
      if (v < 0 || static_cast<std::uint64_t>(v) >= n)
        (w / "triangles")[static_cast<std::size_t>(i)].fail("vertex {} is not one of the {} positions", v, n);
      tri[static_cast<std::size_t>(c)] = static_cast<std::uint32_t>(v);
    }
    s.mesh.triangles.push_back(tri);
  }
  if (m.contains("normals")) {
    const auto a = rows_of<double>(m["normals"], w / "normals", 3, kMaxMeshVertices);
    if (static_cast<std::size_t>(a.shape(0)) != n) (w / "normals").fail("{} normals for {} positions", a.shape(0), n);
    for (std::size_t i = 0; i < n; ++i) {
      const Vec3 v = point(a.data() + 3 * i);
      const double l = length(v);
      if (!std::isfinite(l) || l == 0.0) (w / "normals")[i].fail("expected a finite, non-zero vector");
      s.normals.push_back(v);
    }
  }
  if (m.contains("uvs")) {
    const auto a = rows_of<double>(m["uvs"], w / "uvs", 2, kMaxMeshVertices);
    if (static_cast<std::size_t>(a.shape(0)) != n) (w / "uvs").fail("{} UVs for {} positions", a.shape(0), n);
    for (std::size_t i = 0; i < n; ++i) {
      const std::array<double, 2> uv{a.at(static_cast<py::ssize_t>(i), 0), a.at(static_cast<py::ssize_t>(i), 1)};
      if (!std::isfinite(uv[0]) || !std::isfinite(uv[1])) (w / "uvs")[i].fail("expected finite numbers");
      s.uvs.push_back(uv);
    }
  }
  return s;
}

// The dict goes through Python's json module, so it is read by the same loader as a file: the
// same keys, checks and messages. Relative paths in it are against `base` (the working directory
// when not given); messages name it as "<dict>" in that folder. `meshes` are triangles held in
// memory, named by shapes {"type": "mesh", "arrays": name}.
std::shared_ptr<Scene> load_dict(const py::dict& d, const std::optional<fs::path>& base,
                                 const std::optional<py::dict>& meshes) {
  const std::string text = py::module_::import("json").attr("dumps")(d, py::arg("allow_nan") = false).cast<std::string>();
  const fs::path folder = base ? fs::absolute(*base) : fs::current_path();
  const fs::path file = folder / "<dict>";
  MeshArrays arrays;
  if (meshes) {
    const Source w{file, "meshes"};
    for (const auto& [key, value] : *meshes) {
      const std::string name = py::str(key);
      const Source wn{file, fmt::format("meshes['{}']", name)};
      if (!py::isinstance<py::dict>(value)) wn.fail("expected a dict with 'positions' and 'triangles'");
      arrays.emplace(name, mesh_arrays(value.cast<py::dict>(), wn));
    }
  }
  return scene_from(parse_scene(text, file, meshes ? &arrays : nullptr));
}

struct RenderArgs {
  std::optional<std::int64_t> spp, seed, max_depth;
  std::optional<std::string> integrator, spectral;
  std::optional<std::pair<std::int64_t, std::int64_t>> resolution;
  std::optional<double> time_s;
  std::optional<fs::path> spectral_exr;  // the command line's --spectral-exr
  int threads = 0;
  bool spectra = false;
  py::object progress, on_pass, should_stop;
  bool denoise = false;  // the command line's --denoise (render/denoise.h)
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
  // A budget of seconds without spp: as many samples as the budget allows (as the command line's --time).
  constexpr int kTimedSpp = 1 << 20;
  if (a.time_s && !a.spp) s.spp = kTimedSpp;
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

// What the worker and the calling thread share. The worker renders passes of sample ranges (any
// split gives the same image, render/film.h), 1, 1, 2, 4, ... up to kMaxPassSpp per pixel, so that a
// stop waits for the tiles of one pass at most. After each pass, when the caller wants the image so
// far, it waits until the calling thread has resolved the film (a copy, milliseconds), so that the
// film is never read while it is written.
struct PassState {
  std::mutex mutex;
  std::condition_variable cv;
  bool done = false, pass_waiting = false;
  std::atomic<bool> cancel{false};
  std::atomic<double> fraction{0.0};
  int complete = 0, partial = 0;  // samples every pixel has; those the stopped pass added where it reached
  double partial_fraction = 0.0;  // of the stopped pass's tiles that finished
  std::exception_ptr failure;
};

constexpr int kMaxPassSpp = 64;

double seconds_since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

// The render's passes (integrators/render_into.h: render_passes), at most kMaxPassSpp each, after
// path guiding's training where the settings ask for it (integrators/guiding.h; with a budget, in at
// most a quarter of it, the passes in the rest).
void render_passes(const RenderScene& scene, const RenderSettings& settings, FilmBuffer& film, const RenderArgs& a,
                   RenderStats& stats, PassState& st) {
  const int spp = settings.spp;
  const double budget_s = a.time_s.value_or(0.0);
  const bool hand_over = !a.on_pass.is_none();
  const auto start = std::chrono::steady_clock::now();
  RenderControl control;
  control.threads = a.threads;
  control.cancel = &st.cancel;
  GuideTraining training;
  const auto guide = prepare_guide(scene, settings, control, stats, training, budget_s / 4.0);
  control.guide = guide.get();
  PassOptions options;
  options.first = st.complete;  // samples the film has already (integrator "auto"'s trial)
  options.budget_s = budget_s > 0.0 ? std::max(budget_s - seconds_since(start), 1e-9) : 0.0;
  options.max_pass_spp = kMaxPassSpp;
  const auto passes_start = std::chrono::steady_clock::now();
  options.progress = [&](int begin, int end, double f) {
    const double by_samples = (begin + f * (end - begin)) / spp;
    st.fraction.store(budget_s > 0.0 ? std::min(1.0, std::max(by_samples, seconds_since(passes_start) / options.budget_s))
                                     : by_samples);
  };
  options.after_pass = [&](int complete) {
    std::unique_lock lock(st.mutex);
    st.complete = complete;
    if (hand_over && !st.cancel) {
      st.pass_waiting = true;
      st.cv.notify_all();
      st.cv.wait(lock, [&] { return !st.pass_waiting; });
    }
    return !st.cancel.load();
  };
  const Passes p = render_passes(scene, settings, film, control, options, stats);
  const std::lock_guard lock(st.mutex);
  st.complete = p.complete, st.partial = p.partial, st.partial_fraction = p.partial_fraction;
}

// The image of the samples done so far. Light paths splat anywhere: their scale is the light
// paths traced per pixel (as the command line's).
Film resolved(const FilmBuffer& buffer, const PassState& st) {
  const double splat_spp = st.complete + st.partial * st.partial_fraction;
  return buffer.resolve(splat_spp > 0.0 ? 1.0 / splat_spp : 0.0);
}

py::array_t<float> rgb_array(const Film& film) {
  py::array_t<float> rgb({static_cast<py::ssize_t>(film.height), static_cast<py::ssize_t>(film.width), py::ssize_t{3}});
  std::copy(film.rgb.begin(), film.rgb.end(), rgb.mutable_data());
  return rgb;
}

void note_stats(Scene& scene, const RenderStats& stats, const PassState& st, int spp, bool stopped) {
  scene.stats = RenderReport{stats.seconds, stats.rays, st.complete, spp, stopped, {}};
}

// Calls a Python callback; an exception in it stops the render and is raised once the worker has
// stopped.
template <typename F>
bool call_python(F&& f, std::optional<py::error_already_set>& error, PassState& st) {
  try {
    f();
    return true;
  } catch (py::error_already_set& e) {
    error.emplace(std::move(e));
    st.cancel = true;
    return false;
  }
}

// The render runs on a worker thread without the GIL; the calling thread waits for it, and every
// few tens of milliseconds takes the GIL to look for a signal (Ctrl-C: KeyboardInterrupt), to ask
// should_stop() and to call progress(); after each pass it hands on_pass the image so far. So
// Python code runs on one thread only. Ctrl-C and should_stop() both set the renderer's cancel
// flag: the tiles in flight finish, the rest are skipped. Ctrl-C then raises KeyboardInterrupt;
// should_stop() keeps the samples done, and the render returns their image. Returns whether it was
// stopped.
bool render_waiting(Scene& scene, const RenderScene& compiled, const RenderSettings& settings, FilmBuffer& film,
                    const RenderArgs& a, RenderStats& stats, PassState& st) {
  std::thread worker;
  {
    const py::gil_scoped_release release;
    worker = std::thread([&] {
      try {
        render_passes(compiled, settings, film, a, stats, st);
      } catch (...) {
        st.failure = std::current_exception();
      }
      const std::lock_guard lock(st.mutex);
      st.done = true;
      st.cv.notify_all();
    });
  }
  double reported = -1.0;
  bool interrupted = false, stopped = false;
  std::optional<py::error_already_set> callback_error;
  for (;;) {
    bool finished = false;
    std::optional<Film> so_far;
    {
      const py::gil_scoped_release release;
      std::unique_lock lock(st.mutex);
      st.cv.wait_for(lock, std::chrono::milliseconds(50), [&] { return st.done || st.pass_waiting; });
      finished = st.done;
      if (st.pass_waiting) {
        so_far = resolved(film, st);
        note_stats(scene, stats, st, settings.spp, false);
        st.pass_waiting = false;
        st.cv.notify_all();
      }
    }
    const bool quiet = interrupted || stopped || callback_error;
    if (!quiet && PyErr_CheckSignals() != 0) interrupted = true, st.cancel = true;
    if (!quiet && !interrupted && !a.should_stop.is_none())
      call_python([&] { if (py::bool_(a.should_stop())) stopped = true, st.cancel = true; }, callback_error, st);
    if (so_far && !interrupted && !callback_error)
      call_python([&] { a.on_pass(rgb_array(*so_far), scene.stats.spp_done, settings.spp); }, callback_error, st);
    if (!interrupted && !callback_error && !a.progress.is_none()) {
      const double f = finished && !stopped ? 1.0 : st.fraction.load();
      if (f != reported) reported = f, call_python([&] { a.progress(f); }, callback_error, st);
    }
    if (finished) break;
  }
  {
    const py::gil_scoped_release release;
    worker.join();
  }
  if (callback_error) throw std::move(*callback_error);
  if (interrupted) throw py::error_already_set();  // the KeyboardInterrupt PyErr_CheckSignals set
  if (st.failure) std::rethrow_exception(st.failure);
  return stopped;
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
  const bool keep_spectra = a.spectra || a.spectral_exr;
  check_settings(compiled, settings, keep_spectra);
  if (a.denoise) check_denoisable(settings.integrator, "denoise");
  RenderStats stats;
  PassState st;
  // integrator "auto": the candidates' trials (integrators/choose.h) choose, without the GIL; the
  // chosen one's film goes on from its trial's samples.
  std::optional<EstimatorChoice> choice;
  if (settings.integrator == IntegratorType::automatic) {
    const py::gil_scoped_release release;
    RenderControl control;
    control.threads = a.threads;
    const bool seconds_only = a.time_s && !a.spp;  // as the command line's
    choice.emplace(choose_estimator(compiled, settings, auto_trial_spp(settings.spp, seconds_only),
                                    auto_render_spp(settings.spp, seconds_only), keep_spectra, &scene.desc.display,
                                    control, stats, a.denoise));
  }
  RenderSettings chosen = settings;
  if (choice) chosen.integrator = choice->chosen, chosen.light_paths = chosen.light_paths || choice->light_paths;
  FilmBuffer buffer =
      choice && choice->film ? std::move(*choice->film) : make_film(compiled, keep_spectra, a.denoise);
  if (choice) st.complete = choice->trial_spp;
  const bool stopped = render_waiting(scene, compiled, chosen, buffer, a, stats, st);
  note_stats(scene, stats, st, settings.spp, stopped);
  scene.stats.integrator = std::string(integrator_info(chosen.integrator).name);
  Film film = resolved(buffer, st);
  if (a.denoise) {  // the -o image only, as the command line's: the spectra stay as rendered
    DenoiseSettings ds;
    ds.threads = a.threads;
    const py::gil_scoped_release release;
    denoise(film, half_images(buffer, film), ds);
  }
  if (const NonFinitePixels bad = find_non_finite(film); bad.count > 0)
    fail("{}: {} of {} pixels came out not finite (the first at ({}, {}))", scene.desc.file.string(), bad.count,
         static_cast<std::size_t>(film.width) * static_cast<std::size_t>(film.height), bad.first_x, bad.first_y);
  if (buffer.saturated_splats() > 0)
    PyErr_WarnEx(PyExc_RuntimeWarning,
                 fmt::format("{} light-path splats were not finite or beyond the film's range and were dropped",
                             buffer.saturated_splats())
                     .c_str(),
                 1);
  if (a.spectral_exr) write_spectral_exr(*a.spectral_exr, film);
  py::array_t<float> rgb = rgb_array(film);
  if (!a.spectra) return rgb;
  const auto h = static_cast<py::ssize_t>(film.height), w = static_cast<py::ssize_t>(film.width);
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
      .def_property_readonly("integrator",
                             [](const Scene& s) { return std::string(bouguer::integrator_info(s.desc.render.integrator).name); })
      .def_property_readonly("spectral",
                             [](const Scene& s) { return std::string(bouguer::spectral_mode_name(s.desc.render.spectral)); })
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
      .def_property_readonly("stats",
                             [](const Scene& s) {
                               const RenderReport& r = s.stats;
                               py::dict d;
                               d["seconds"] = r.seconds;
                               d["rays"] = r.rays;
                               d["rays_per_second"] = r.seconds > 0 ? static_cast<double>(r.rays) / r.seconds : 0.0;
                               d["spp"] = r.spp_done;
                               d["spp_requested"] = r.spp_requested;
                               d["stopped"] = r.stopped;
                               d["integrator"] = r.integrator;
                               return d;
                             })
      .def("__repr__", [](const Scene& s) {
        return fmt::format("<bouguer.Scene {} {}x{}>", s.desc.file.string(), s.compiled->camera.width_px,
                           s.compiled->camera.height_px);
      });

  register_tools(m);
  m.def(
      "reflectance_spectrum",
      [](const std::array<double, 3>& rgb, const py::array_t<double, py::array::c_style | py::array::forcecast>& nm) {
        // The lift every {"rgb": ...} reflectance gets (Jakob & Hanika 2019): front ends that build
        // spectra from colours themselves (Blender's volumes) lift them the same way.
        const bouguer::SigmoidPolynomial lift = bouguer::rgb_to_reflectance({rgb[0], rgb[1], rgb[2]});
        py::array_t<double> out(nm.request().shape);
        const double* in = nm.data();
        double* o = out.mutable_data();
        for (py::ssize_t i = 0; i < nm.size(); ++i) {
          if (!(std::isfinite(in[i]) && in[i] > 0.0)) bouguer::fail("reflectance_spectrum: wavelengths must be positive nm");
          o[i] = lift(in[i]);
        }
        return out;
      },
      py::arg("rgb"), py::arg("wavelength_nm"),
      "The smooth reflectance spectrum of a linear Rec.709 colour (components clamped to [0, 1]) at wavelengths "
      "in nm: the lift of every {\"rgb\": ...} reflectance (docs/scene-format.md)");
  m.def(
      "attenuation_spectrum",
      [](const std::array<double, 3>& colour, double distance_m) {
        // The glTF reader's lift of an attenuation colour (scene/pbr_material.h), for front ends that
        // give a medium per-channel coefficients (Blender's volumes): one lift, not a copy of it.
        for (double c : colour)
          if (!(c > 0.0 && c <= 1.0)) bouguer::fail("attenuation_spectrum: each channel must lie in (0, 1] (got {})", c);
        if (!(distance_m > 0.0 && std::isfinite(distance_m)))
          bouguer::fail("attenuation_spectrum: the distance must be a positive length (got {} m)", distance_m);
        const bouguer::TableInput t = bouguer::attenuation_sigma_a({colour[0], colour[1], colour[2]}, distance_m);
        return py::make_tuple(py::array_t<double>(static_cast<py::ssize_t>(t.wavelength_nm.size()), t.wavelength_nm.data()),
                              py::array_t<double>(static_cast<py::ssize_t>(t.value.size()), t.value.data()));
      },
      py::arg("colour"), py::arg("distance_m"),
      "(wavelength_nm, sigma_a_per_m): the absorption whose transmittance over distance_m is `colour` per "
      "channel, exactly at the rgb3 lines (the glTF reader's KHR_materials_volume lift, docs/assets.md)");
  m.def("load", &load, py::arg("path"), "Load and compile a scene file (JSON, docs/scene-format.md)");
  m.def("load_dict", &load_dict, py::arg("scene"), py::arg("base") = py::none(), py::arg("meshes") = py::none(),
        "Load and compile a scene from a dict with the JSON schema; relative paths against `base` (default: the "
        "working directory); meshes={name: {'positions': (N, 3), 'triangles': (M, 3), 'normals': (N, 3), 'uvs': "
        "(N, 2)}} for shapes {'type': 'mesh', 'arrays': name}");
  m.def(
      "render",
      [](Scene& scene, std::optional<std::int64_t> spp, std::optional<std::string> integrator,
         std::optional<std::string> spectral, std::optional<std::int64_t> seed, int threads,
         std::optional<std::pair<std::int64_t, std::int64_t>> resolution, std::optional<std::int64_t> max_depth,
         bool spectra, py::object progress, std::optional<double> time_s, py::object on_pass, py::object should_stop,
         std::optional<fs::path> spectral_exr, bool denoise) {
        if (threads < 0 || threads > 1024) bouguer::fail_usage("threads: must be between 0 and 1024 (got {})", threads);
        if (time_s && !(std::isfinite(*time_s) && *time_s > 0.0))
          bouguer::fail_usage("time_s: must be a positive number of seconds (got {})", *time_s);
        RenderArgs a{spp,      seed,    max_depth,           std::move(integrator), std::move(spectral),
                     resolution, time_s, {},      threads,               spectra,               std::move(progress),
                     std::move(on_pass), std::move(should_stop)};
        a.spectral_exr = std::move(spectral_exr);
        a.denoise = denoise;
        return render(scene, a);
      },
      py::arg("scene"), py::kw_only(), py::arg("spp") = py::none(), py::arg("integrator") = py::none(),
      py::arg("spectral") = py::none(), py::arg("seed") = py::none(), py::arg("threads") = 0,
      py::arg("resolution") = py::none(), py::arg("max_depth") = py::none(), py::arg("spectra") = false,
      py::arg("progress") = py::none(), py::arg("time_s") = py::none(), py::arg("on_pass") = py::none(),
      py::arg("should_stop") = py::none(), py::arg("spectral_exr") = py::none(), py::arg("denoise") = false,
      "Render: a float32 (H, W, 3) array, linear Rec.709, row 0 at the top; with spectra=True a tuple (rgb, "
      "spectra (H, W, N), wavelengths_nm (N,)). Keyword arguments override the scene's settings (the command "
      "line's names). progress(fraction) is called now and then; Ctrl-C stops the render (KeyboardInterrupt). "
      "time_s: a budget of seconds (the command line's --time). on_pass(rgb_so_far, samples_done, spp) after each "
      "pass; should_stop() polled every 50 ms: True ends the render and returns the image of the samples done. "
      "spectral_exr: a path, the command line's --spectral-exr. denoise=True: the rgb image filtered from its two half "
      "buffers (the command line's --denoise; biased, deterministic; spectra stay as rendered). Scene.stats describes the render (also during on_pass).");
}

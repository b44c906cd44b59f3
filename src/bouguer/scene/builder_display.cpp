// SceneBuilder's display settings (io/display.h): each value checked here, once, for the scene
// file, the command line and every other front end.
#include <cmath>

#include "bouguer/core/strings.h"
#include "bouguer/scene/builder.h"
#include "bouguer/spectra/cie.h"

namespace bouguer {
namespace {

constexpr double kMaxEv = 32.0;  // ±32 EV: a factor of 4·10⁹ either way, far beyond any real scene

void check_positive(double v, const Source& where, const char* what) {
  if (!(v > 0.0) || !std::isfinite(v)) where.fail("{} must be a positive number (got {})", what, v);
}

}  // namespace

SceneBuilder& SceneBuilder::exposure_ev(double ev, const Source& where) {
  if (!(std::abs(ev) <= kMaxEv)) where.fail("must be between {} and {} EV (got {})", -kMaxEv, kMaxEv, ev);
  desc_.display.exposure_ev = ev;
  return *this;
}

SceneBuilder& SceneBuilder::camera_exposure(const CameraExposure& c, const Source& where) {
  check_positive(c.iso, where, "the ISO speed");
  check_positive(c.shutter_s, where, "the shutter time (s)");
  check_positive(c.f_number, where, "the f-number");
  if (!std::isfinite(ev100(c))) where.fail("gives no finite exposure value");
  desc_.display.camera = c;
  desc_.display.auto_exposure = false;
  return *this;
}

SceneBuilder& SceneBuilder::auto_exposure(bool on) {
  desc_.display.auto_exposure = on;
  if (on) desc_.display.camera.reset();
  return *this;
}

SceneBuilder& SceneBuilder::white_balance(const std::string& name, const Source& where) {
  if (name == "none") {
    desc_.display.white_balance = NoWhiteBalance{};
    return *this;
  }
  if (name == "brightest_emitter") {
    desc_.display.white_balance = BrightestEmitterWhite{};
    return *this;
  }
  std::optional<Spectrum> spd;
  try {
    spd = named_illuminant_spd(name);
  } catch (const Error& e) {
    where.fail("{}", e.what());
  }
  if (!spd) {
    std::vector<std::string> names = illuminant_names();
    names.insert(names.end(), {"brightest_emitter", "none"});
    where.fail("unknown white '{}'{}", name, suggestion(name, names));
  }
  desc_.display.white_balance = IlluminantWhite{name, spectrum_to_xyz(normalised_to_luminance(*spd, 1.0))};
  return *this;
}

SceneBuilder& SceneBuilder::display_curve(const std::string& name, const Source& where) {
  if (name == "clip")
    desc_.display.curve = DisplayCurve::clip;
  else if (name == "filmic")
    desc_.display.curve = DisplayCurve::filmic;
  else
    where.fail("unknown display curve '{}'{}", name, suggestion(name, {"clip", "filmic"}));
  return *this;
}

SceneBuilder& SceneBuilder::expose_float_outputs(bool on) {
  desc_.display.float_outputs = on;
  return *this;
}

}  // namespace bouguer

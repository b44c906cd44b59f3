#include "bouguer/plot/material_plot.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "bouguer/core/error.h"
#include "bouguer/io/atomic_file.h"
#include "bouguer/spectra/color_space.h"

namespace bouguer {
namespace {

constexpr double kWidth = 1200.0, kHeight = 900.0;
constexpr const char* kFont = "DejaVu Sans";

struct Rgb {
  double r, g, b;
};
// Line colours for the thickness curves (Okabe–Ito, readable by colour-blind viewers).
constexpr Rgb kPalette[] = {{0.0, 0.45, 0.70}, {0.90, 0.62, 0.0},  {0.0, 0.62, 0.45}, {0.80, 0.40, 0.0},
                            {0.35, 0.70, 0.90}, {0.80, 0.60, 0.70}, {0.0, 0.0, 0.0},   {0.94, 0.89, 0.26}};

// "Nice" tick values (1, 2, 5 × 10^k) covering [lo, hi].
std::vector<double> ticks(double lo, double hi, int target = 6) {
  const double span = hi - lo;
  if (!(span > 0.0)) return {lo};
  const double raw = span / target, mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double step = raw / mag < 1.5 ? mag : raw / mag < 3.5 ? 2 * mag : raw / mag < 7.5 ? 5 * mag : 10 * mag;
  std::vector<double> out;
  for (double v = std::ceil(lo / step - 1e-9) * step; v <= hi + step * 1e-9; v += step) out.push_back(v);
  if (out.empty() || out.back() < hi) out.push_back((out.empty() ? lo : out.back()) + step);  // the top covers hi
  return out;
}

std::string label(double v) {
  if (v == 0.0) return "0";
  const double a = std::abs(v);
  if (a >= 1e4 || a < 1e-3) return fmt::format("{:.0e}", v);
  return fmt::format("{:g}", v);
}

// A plot area: data ranges mapped to a pixel rectangle; x may be logarithmic.
struct Panel {
  double x0, y0, w, h;  // pixels: left, top, width, height of the data area
  double xlo, xhi, ylo, yhi;
  bool xlog = false;
  double px(double x) const {
    const double t = xlog ? (std::log(x) - std::log(xlo)) / (std::log(xhi) - std::log(xlo)) : (x - xlo) / (xhi - xlo);
    return x0 + t * w;
  }
  double py(double y) const { return y0 + h - (y - ylo) / (yhi - ylo) * h; }
};

void text(cairo_t* cr, double x, double y, const std::string& s, double size, double align_x = 0.0,
          double align_y = 0.0, bool bold = false) {
  cairo_select_font_face(cr, kFont, CAIRO_FONT_SLANT_NORMAL, bold ? CAIRO_FONT_WEIGHT_BOLD : CAIRO_FONT_WEIGHT_NORMAL);
  cairo_set_font_size(cr, size);
  cairo_text_extents_t e;
  cairo_text_extents(cr, s.c_str(), &e);
  cairo_move_to(cr, x - align_x * e.width - e.x_bearing, y - align_y * e.height - e.y_bearing);
  cairo_show_text(cr, s.c_str());
}

void vertical_text(cairo_t* cr, double x, double y, const std::string& s, double size) {
  cairo_save(cr);
  cairo_translate(cr, x, y);
  cairo_rotate(cr, -M_PI / 2.0);
  text(cr, 0, 0, s, size, 0.5, 0.5);
  cairo_restore(cr);
}

void axes(cairo_t* cr, const Panel& p, const std::string& title, const std::string& xlabel, const std::string& ylabel,
          const std::vector<double>& xt, const std::vector<double>& yt) {
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, p.x0, p.y0 - 26, title, 15, 0.0, 0.5, true);
  cairo_set_line_width(cr, 1.0);
  for (double v : yt) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, p.x0, p.py(v));
    cairo_line_to(cr, p.x0 + p.w, p.py(v));
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, p.x0 - 6, p.py(v), label(v), 11, 1.0, 0.5);
  }
  for (double v : xt) {
    cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
    cairo_move_to(cr, p.px(v), p.y0);
    cairo_line_to(cr, p.px(v), p.y0 + p.h);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    text(cr, p.px(v), p.y0 + p.h + 6, p.xlog ? format_thickness(v) : label(v), 11, 0.5, 0.0);
  }
  cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
  cairo_rectangle(cr, p.x0, p.y0, p.w, p.h);
  cairo_stroke(cr);
  text(cr, p.x0 + p.w / 2, p.y0 + p.h + 26, xlabel, 12, 0.5, 0.0);
  vertical_text(cr, p.x0 - 62, p.y0 + p.h / 2, ylabel, 12);
}

void clip_to(cairo_t* cr, const Panel& p) {
  cairo_save(cr);
  cairo_rectangle(cr, p.x0, p.y0, p.w, p.h);
  cairo_clip(cr);
}

void legend(cairo_t* cr, double x, double y, const std::vector<std::pair<std::string, Rgb>>& entries) {
  for (std::size_t i = 0; i < entries.size(); ++i) {
    const double yy = y + 16.0 * static_cast<double>(i);
    cairo_set_source_rgb(cr, entries[i].second.r, entries[i].second.g, entries[i].second.b);
    cairo_set_line_width(cr, 2.5);
    cairo_move_to(cr, x, yy);
    cairo_line_to(cr, x + 22, yy);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    text(cr, x + 28, yy, entries[i].first, 11, 0.0, 0.5);
  }
}

void draw(cairo_t* cr, const MaterialPlot& m) {
  const ThicknessAnalysis& a = m.analysis;
  cairo_set_source_rgb(cr, 1, 1, 1);
  cairo_paint(cr);
  cairo_set_source_rgb(cr, 0.05, 0.05, 0.05);
  text(cr, 24, 22, fmt::format("{}{}", m.name, m.concentration_note.empty() ? "" : " at " + m.concentration_note), 20,
       0.0, 0.5, true);
  text(cr, kWidth - 24, 22,
       fmt::format("slab in air, n = {:.3f}, normal incidence, under {} (Y = 1); CIE 1931 2°", a.ior, m.illuminant),
       12, 1.0, 0.5);

  // 1. Absorption spectrum.
  double smax = 0.0;
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) smax = std::max(smax, eval(m.sigma_a_per_m, nm));
  if (!(smax > 0.0)) smax = 1.0;
  const std::vector<double> yt1 = ticks(0.0, smax * 1.05);
  const Panel p1{100, 90, 440, 300, kLambdaMinNm, kLambdaMaxNm, 0.0, yt1.back(), false};
  if (m.extended) {
    cairo_set_source_rgb(cr, 0.93, 0.93, 0.93);
    cairo_rectangle(cr, p1.px(kLambdaMinNm), p1.y0, p1.px(m.measured_min_nm) - p1.px(kLambdaMinNm), p1.h);
    cairo_rectangle(cr, p1.px(m.measured_max_nm), p1.y0, p1.px(kLambdaMaxNm) - p1.px(m.measured_max_nm), p1.h);
    cairo_fill(cr);
  }
  axes(cr, p1, "Absorption spectrum", "wavelength (nm)", "σₐ (natural log, per m)", ticks(400, 800, 5), yt1);
  clip_to(cr, p1);
  cairo_set_source_rgb(cr, 0.55, 0.1, 0.1);
  cairo_set_line_width(cr, 2.0);
  for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
    const double x = p1.px(nm), y = p1.py(eval(m.sigma_a_per_m, nm));
    nm == kLambdaMinNm ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
  }
  cairo_stroke(cr);
  cairo_restore(cr);
  if (m.extended) {
    cairo_set_source_rgb(cr, 0.4, 0.4, 0.4);
    text(cr, p1.x0 + p1.w - 4, p1.y0 + 6, fmt::format("grey: extended outside {:g}-{:g} nm", m.measured_min_nm,
                                                      m.measured_max_nm), 10, 1.0, 0.0);
  }

  // 2. Internal transmittance for each thickness.
  const Panel p2{700, 90, 380, 300, kLambdaMinNm, kLambdaMaxNm, 0.0, 1.0, false};
  axes(cr, p2, "Internal transmittance τ = exp(−σₐ d)", "wavelength (nm)", "τ", ticks(400, 800, 5), ticks(0, 1, 5));
  std::vector<std::pair<std::string, Rgb>> entries;
  clip_to(cr, p2);
  for (std::size_t i = 0; i < a.rows.size(); ++i) {
    const Rgb c = kPalette[i % std::size(kPalette)];
    cairo_set_source_rgb(cr, c.r, c.g, c.b);
    cairo_set_line_width(cr, 2.0);
    for (double nm = kLambdaMinNm; nm <= kLambdaMaxNm; nm += 1.0) {
      const double x = p2.px(nm), y = p2.py(std::exp(-eval(m.sigma_a_per_m, nm) * a.rows[i].thickness_m));
      nm == kLambdaMinNm ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    cairo_stroke(cr);
    entries.emplace_back(format_thickness(a.rows[i].thickness_m), c);
  }
  cairo_restore(cr);
  legend(cr, p2.x0 + p2.w + 12, p2.y0 + 8, entries);

  // 3. Swatches: the slab's colour from thin to thick.
  const double sx = 100, sy = 490, sw = 440, row_h = 58;
  cairo_set_source_rgb(cr, 0.1, 0.1, 0.1);
  text(cr, sx, sy - 26, "Colour of the slab, thin to thick", 15, 0.0, 0.5, true);
  const std::size_t n = std::max<std::size_t>(1, a.rows.size());
  const double cw = sw / static_cast<double>(n);
  const char* names[] = {"spectral", "rgb3 (paper)", "RGB fitted"};
  for (int r = 0; r < 3; ++r) {
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    text(cr, sx - 8, sy + r * row_h + row_h / 2 - 4, names[r], 11, 1.0, 0.5);
    for (std::size_t i = 0; i < a.rows.size(); ++i) {
      const SlabColour& c = r == 0 ? a.rows[i].spectral : r == 1 ? a.rows[i].rgb3 : a.rows[i].fitted;
      cairo_set_source_rgb(cr, srgb_encode(std::clamp(c.linear_srgb.x, 0.0, 1.0)),
                           srgb_encode(std::clamp(c.linear_srgb.y, 0.0, 1.0)),
                           srgb_encode(std::clamp(c.linear_srgb.z, 0.0, 1.0)));
      cairo_rectangle(cr, sx + cw * static_cast<double>(i) + 1, sy + r * row_h, cw - 2, row_h - 8);
      cairo_fill(cr);
    }
  }
  cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
  for (std::size_t i = 0; i < a.rows.size(); ++i)
    text(cr, sx + cw * (static_cast<double>(i) + 0.5), sy + 3 * row_h + 2, format_thickness(a.rows[i].thickness_m), 11,
         0.5, 0.0);
  text(cr, sx, sy + 3 * row_h + 24,
       fmt::format("RGB fitted: per-channel σₐ chosen to match the spectral colour at {}",
                   format_thickness(a.reference_thickness_m)),
       11, 0.0, 0.0);
  text(cr, sx, sy + 3 * row_h + 42, "rgb3: σₐ at 700.0, 546.1, 435.8 nm applied to R, G, B", 11, 0.0, 0.0);

  // 4. ΔE00 of the shortcuts against thickness.
  double emax = 1.0;
  for (const ThicknessRow& r : a.rows) emax = std::max({emax, r.delta_e_rgb3, r.delta_e_fitted});
  const std::vector<double> yt4 = ticks(0.0, emax * 1.1);
  double dlo = a.rows.empty() ? 1e-3 : a.rows.front().thickness_m, dhi = dlo;
  for (const ThicknessRow& r : a.rows) {
    dlo = std::min(dlo, r.thickness_m);
    dhi = std::max(dhi, r.thickness_m);
  }
  if (dhi <= dlo) dhi = dlo * 2.0;
  const Panel p4{700, 490, 440, 300, dlo / 1.3, dhi * 1.3, 0.0, yt4.back(), true};
  std::vector<double> xt4;
  for (const ThicknessRow& r : a.rows) xt4.push_back(r.thickness_m);
  axes(cr, p4, "Error of the RGB shortcuts", "thickness (log scale)", "ΔE00 against the spectral colour", xt4, yt4);
  clip_to(cr, p4);
  cairo_set_source_rgb(cr, 0.6, 0.6, 0.6);
  cairo_set_dash(cr, std::array<double, 2>{4, 4}.data(), 2, 0);
  cairo_move_to(cr, p4.px(a.reference_thickness_m), p4.y0);
  cairo_line_to(cr, p4.px(a.reference_thickness_m), p4.y0 + p4.h);
  cairo_stroke(cr);
  cairo_set_dash(cr, nullptr, 0, 0);
  const Rgb series_colour[2] = {{0.80, 0.15, 0.15}, {0.15, 0.35, 0.80}};
  for (int s = 0; s < 2; ++s) {
    cairo_set_source_rgb(cr, series_colour[s].r, series_colour[s].g, series_colour[s].b);
    cairo_set_line_width(cr, 2.0);
    for (std::size_t i = 0; i < a.rows.size(); ++i) {
      const double e = s == 0 ? a.rows[i].delta_e_rgb3 : a.rows[i].delta_e_fitted;
      const double x = p4.px(a.rows[i].thickness_m), y = p4.py(e);
      i == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    cairo_stroke(cr);
    for (const ThicknessRow& r : a.rows) {
      cairo_arc(cr, p4.px(r.thickness_m), p4.py(s == 0 ? r.delta_e_rgb3 : r.delta_e_fitted), 3.5, 0, 2 * M_PI);
      cairo_fill(cr);
    }
  }
  cairo_restore(cr);
  legend(cr, p4.x0 + 12, p4.y0 + 14,
         {{"rgb3 (paper's RGB tracer)", series_colour[0]},
          {fmt::format("RGB fitted at {}", format_thickness(a.reference_thickness_m)), series_colour[1]}});
}

cairo_status_t append(void* closure, const unsigned char* data, unsigned int length) {
  static_cast<std::string*>(closure)->append(reinterpret_cast<const char*>(data), length);
  return CAIRO_STATUS_SUCCESS;
}

}  // namespace

std::string render_material_plot(const MaterialPlot& plot, const std::string& format) {
  std::string bytes;
  cairo_surface_t* surface = nullptr;
  if (format == "svg") surface = cairo_svg_surface_create_for_stream(append, &bytes, kWidth, kHeight);
  else if (format == "pdf") surface = cairo_pdf_surface_create_for_stream(append, &bytes, kWidth, kHeight);
  else if (format == "png") surface = cairo_image_surface_create(CAIRO_FORMAT_RGB24, static_cast<int>(kWidth), static_cast<int>(kHeight));
  else fail("unknown plot format '{}' (svg, png or pdf)", format);
  cairo_t* cr = cairo_create(surface);
  draw(cr, plot);
  const cairo_status_t status = cairo_status(cr);
  cairo_destroy(cr);
  if (format == "png" && status == CAIRO_STATUS_SUCCESS) cairo_surface_write_to_png_stream(surface, append, &bytes);
  cairo_surface_finish(surface);
  const cairo_status_t surface_status = cairo_surface_status(surface);
  cairo_surface_destroy(surface);
  if (status != CAIRO_STATUS_SUCCESS || surface_status != CAIRO_STATUS_SUCCESS)
    fail("drawing the plot failed: {}", cairo_status_to_string(status != CAIRO_STATUS_SUCCESS ? status : surface_status));
  return bytes;
}

void write_material_plot(const std::filesystem::path& path, const MaterialPlot& plot) {
  std::string ext = path.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  if (ext != ".svg" && ext != ".png" && ext != ".pdf")
    fail("{}: a plot is written as .svg, .png or .pdf", path.string());
  write_bytes_atomically(path, render_material_plot(plot, ext.substr(1)));
}

}  // namespace bouguer

#include "bouguer/media/ior.h"

#include <cmath>

namespace bouguer {

double sellmeier_ior(const SellmeierIor& s, double wavelength_nm) {
  const double l2 = (wavelength_nm * 1e-3) * (wavelength_nm * 1e-3);
  double n2 = 1.0;
  for (std::size_t i = 0; i < s.B.size(); ++i) n2 += s.B[i] * l2 / (l2 - s.C_um2[i]);
  return std::sqrt(n2);
}

double cauchy_ior(const CauchyIor& c, double wavelength_nm) {
  const double l2 = (wavelength_nm * 1e-3) * (wavelength_nm * 1e-3);
  return c.A + c.B_um2 / l2 + c.C_um4 / (l2 * l2);
}

double ior_at(const IorModel& model, double wavelength_nm) {
  struct Visitor {
    double nm;
    double operator()(const ConstantIor& c) const { return c.n; }
    double operator()(const SellmeierIor& s) const { return sellmeier_ior(s, nm); }
    double operator()(const CauchyIor& c) const { return cauchy_ior(c, nm); }
    double operator()(const TabulatedIor& t) const { return eval(t.n, nm); }
  };
  return std::visit(Visitor{wavelength_nm}, model);
}

}  // namespace bouguer

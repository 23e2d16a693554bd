#include "pkm/kinematics/elastic_catenary.hpp"

#include <cmath>

namespace pkm {

double asinh_difference(double a, double delta) {
  const double b = a + delta;
  if (delta == 0.0) return 0.0;
  // With a and b on the same side of zero the plain difference cancels; asinh of
  // b sqrt(1 + a^2) - a sqrt(1 + b^2), rewritten as a quotient with no difference left, does not.
  if ((a >= 0.0 && b >= 0.0) || (a <= 0.0 && b <= 0.0)) {
    const double numerator = delta * (a + b);
    const double denominator = b * std::sqrt(1.0 + a * a) + a * std::sqrt(1.0 + b * b);
    if (denominator == 0.0) return std::asinh(b) - std::asinh(a);
    return std::asinh(numerator / denominator);
  }
  return std::asinh(b) - std::asinh(a);
}

CatenarySpan catenary_span(double horizontal_N, double vertical_N, double length_mm,
                           double weight_N_per_mm, double compliance_per_N) {
  const double h = horizontal_N;
  const double a = vertical_N / h;  // slope at the lower end
  CatenarySpan span;
  // The stretch: each element lengthens by its tension times the compliance; integrated, the
  // horizontal part is H L / EA and the vertical part (V L + w L^2 / 2) / EA.
  span.across_mm = h * length_mm * compliance_per_N;
  span.rise_mm =
      (vertical_N * length_mm + 0.5 * weight_N_per_mm * length_mm * length_mm) * compliance_per_N;
  if (weight_N_per_mm > 0.0) {
    const double delta = weight_N_per_mm * length_mm / h;  // slope gained over the cable
    const double b = a + delta;                            // slope at the upper end
    span.across_mm += h / weight_N_per_mm * asinh_difference(a, delta);
    // (H / w)(sqrt(1 + b^2) - sqrt(1 + a^2)), with the difference of roots as a quotient.
    span.rise_mm += length_mm * (a + b) / (std::sqrt(1.0 + a * a) + std::sqrt(1.0 + b * b));
  } else {
    const double root = std::sqrt(1.0 + a * a);
    span.across_mm += length_mm / root;
    span.rise_mm += length_mm * a / root;
  }
  return span;
}

}  // namespace pkm

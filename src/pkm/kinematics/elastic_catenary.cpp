#include "pkm/kinematics/elastic_catenary.hpp"

#include <cmath>

namespace pkm::kinematics {

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

CatenarySpanDerivatives catenary_span_derivatives(double horizontal_N, double vertical_N,
                                                  double length_mm, double weight_N_per_mm,
                                                  double compliance_per_N) {
  const double h = horizontal_N, c = compliance_per_N, w = weight_N_per_mm;
  const double a = vertical_N / h;
  CatenarySpanDerivatives d;
  d.across_by_horizontal = length_mm * c;
  d.rise_by_vertical = length_mm * c;
  d.across_by_length = h * c;
  d.rise_by_length = (vertical_N + w * length_mm) * c;
  if (w > 0.0) {
    const double delta = w * length_mm / h, b = a + delta;
    const double root_a = std::sqrt(1.0 + a * a), root_b = std::sqrt(1.0 + b * b);
    // d/dH of (H / w)(asinh b - asinh a) with a = V / H, b = (V + w L) / H, and so on.
    d.across_by_horizontal += (asinh_difference(a, delta) - (b / root_b - a / root_a)) / w;
    d.across_by_vertical += (1.0 / root_b - 1.0 / root_a) / w;
    d.across_by_length += 1.0 / root_b;
    d.rise_by_horizontal += (1.0 / root_b - 1.0 / root_a) / w;
    d.rise_by_vertical += (b / root_b - a / root_a) / w;
    d.rise_by_length += b / root_b;
  } else {
    // A straight cable: across = H L / T, rise = V L / T, T = sqrt(H^2 + V^2).
    const double t = std::hypot(h, vertical_N), t3 = t * t * t;
    d.across_by_horizontal += length_mm * vertical_N * vertical_N / t3;
    d.across_by_vertical += -length_mm * h * vertical_N / t3;
    d.across_by_length += h / t;
    d.rise_by_horizontal += -length_mm * h * vertical_N / t3;
    d.rise_by_vertical += length_mm * h * h / t3;
    d.rise_by_length += vertical_N / t;
  }
  return d;
}

}  // namespace pkm::kinematics

// The elastic catenary (Irvine, "Cable Structures", 1981, ch. 2): a cable of uniform weight that
// stretches linearly, hanging in a vertical plane, described from its lower end up. Used by the
// cable plotter for sagging chains and stretching cords; with no weight it is a straight cable.
#pragma once

namespace pkm::kinematics {

// Where the cable's upper end is, relative to its lower end: `across_mm` horizontally (towards
// the side the horizontal tension pulls the lower end) and `rise_mm` upwards.
struct CatenarySpan {
  double across_mm = 0.0;
  double rise_mm = 0.0;
};

// The span of a cable whose lower end is pulled by a horizontal tension `horizontal_N` (> 0) and
// lifted by `vertical_N` (the upward force the cable exerts there; negative where the cable dips
// below its lower end first), of unstretched length `length_mm`, weight `weight_N_per_mm` per
// unstretched mm (>= 0) and compliance `compliance_per_N` (1 / EA, >= 0).
CatenarySpan catenary_span(double horizontal_N, double vertical_N, double length_mm,
                           double weight_N_per_mm, double compliance_per_N);

// The span's partial derivatives in H, V and L (mm per N, mm per N, mm per mm), for Newton.
struct CatenarySpanDerivatives {
  double across_by_horizontal = 0.0, across_by_vertical = 0.0, across_by_length = 0.0;
  double rise_by_horizontal = 0.0, rise_by_vertical = 0.0, rise_by_length = 0.0;
};
CatenarySpanDerivatives catenary_span_derivatives(double horizontal_N, double vertical_N,
                                                  double length_mm, double weight_N_per_mm,
                                                  double compliance_per_N);

// asinh(a + delta) - asinh(a) for delta >= 0, without the cancellation of the plain difference
// when delta is small (a light chain's span).
double asinh_difference(double a, double delta);

}  // namespace pkm::kinematics

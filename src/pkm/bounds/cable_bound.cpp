// Interval bounds on a hanging effector's balance over a box of pen positions (cable_bound.hpp;
// the argument is in docs/cable-bounds.md).
#include "pkm/bounds/cable_bound.hpp"

#include <algorithm>
#include <limits>
#include <numbers>

namespace pkm::bounds {

namespace {

constexpr double kPi = std::numbers::pi;
// The cables leave the left pulley on its right (+1) and the right one on its left (-1): the
// tangent turns the centre-to-end direction clockwise (+1) or counter-clockwise (-1) by asin(r/d).
constexpr double kTangentTurn[2] = {1.0, -1.0};
// The balance's tilt search range (cable_statics.cpp: Newton and its scan stay within 1.5 rad).
constexpr double kTiltSearch_rad = 1.5 + 1e-6;
constexpr double kTiltLeaf_rad = 1e-12;
// Double arithmetic rounds to nearest, not outwards: every bound is widened by this much
// relative to its size (the balance itself is solved to about 1e-13).
constexpr double kRounding = 1e-10;

Range operator+(Range a, Range b) {
  return {a.lo + b.lo, a.hi + b.hi};
}
Range operator-(Range a, Range b) {
  return {a.lo - b.hi, a.hi - b.lo};
}
Range operator-(Range a) {
  return {-a.hi, -a.lo};
}
Range operator+(Range a, double k) {
  return {a.lo + k, a.hi + k};
}

Range operator*(Range a, Range b) {
  if (!a.known() || !b.known()) return {};
  const double p[4] = {a.lo * b.lo, a.lo * b.hi, a.hi * b.lo, a.hi * b.hi};
  return {*std::min_element(p, p + 4), *std::max_element(p, p + 4)};
}
Range operator*(double k, Range a) {
  return Range::point(k) * a;
}

Range divided(Range a, Range b) {
  if (!(b.lo > 0.0) && !(b.hi < 0.0)) return {};
  return a * Range{1.0 / b.hi, 1.0 / b.lo};
}

// sin over an interval: its ends, and 1 (-1) where the interval holds pi/2 (-pi/2) + 2 k pi.
Range sin_of(Range a) {
  if (!a.known() || a.hi - a.lo >= 2.0 * kPi) return {-1.0, 1.0};
  const auto holds = [&](double peak) {
    const double k = std::ceil((a.lo - peak) / (2.0 * kPi));
    return peak + 2.0 * kPi * k <= a.hi;
  };
  Range out{std::min(std::sin(a.lo), std::sin(a.hi)), std::max(std::sin(a.lo), std::sin(a.hi))};
  if (holds(0.5 * kPi)) out.hi = 1.0;
  if (holds(-0.5 * kPi)) out.lo = -1.0;
  return out;
}
Range cos_of(Range a) {
  return sin_of(a + 0.5 * kPi);
}

Range abs_of(Range a) {
  if (a.lo >= 0.0) return a;
  if (a.hi <= 0.0) return -a;
  return {0.0, std::max(-a.lo, a.hi)};
}

bool holds_value(Range a, double v) {
  return a.lo <= v && v <= a.hi;
}

Range operator*(Range a, double k) {
  return Range::point(k) * a;
}

Range widened(Range a) {
  return {a.lo - kRounding * std::abs(a.lo), a.hi + kRounding * std::abs(a.hi)};
}

// A box of points in the plane as the range of each coordinate: the interval arithmetic here
// adds, turns and multiplies boxes coordinate by coordinate (Eigen::AlignedBox2d has none of it).
struct Box2 {
  Range x, y;
};

// The distance from the origin of the points of a box.
Range norm_of(const Box2& b) {
  const auto nearest = [](Range r) { return r.lo > 0.0 ? r.lo : (r.hi < 0.0 ? -r.hi : 0.0); };
  const auto farthest = [](Range r) { return std::max(std::abs(r.lo), std::abs(r.hi)); };
  return {std::hypot(nearest(b.x), nearest(b.y)), std::hypot(farthest(b.x), farthest(b.y))};
}

// The angle in (-pi, pi] that turns `from` into `to`.
double turn_between(double from, double to) {
  return std::remainder(to - from, 2.0 * kPi);
}

// A straight cable from its pulley to every end in a box: gamma, the angle between straight
// down and the cable's pull on the effector, measured towards the cable's own pulley (both
// cables pull while both gammas and their sum lie in (0, pi)), and the span from the tangent.
struct CableRange {
  Range gamma, span_mm;
};

// The cable's direction from straight down, counter-clockwise, for an end at `from_centre` of
// its pulley: the centre-to-end direction turned by asin(r / d) onto the tangent.
double cable_direction(int cable, const Eigen::Vector2d& from_centre, double r) {
  return std::atan2(from_centre.x(), -from_centre.y()) -
         kTangentTurn[cable] * std::asin(r / from_centre.norm());
}

// Exact over the box: the ends with one cable direction lie on one half-line (the tangent beyond
// its tangent point), so along any segment clear of the pulley the direction is one-to-one and
// monotone, and over a box clear of it the extremes lie at the corners. The corners' directions
// are unwrapped around the box's edges (an edge sweeps less than a half turn).
bool cable_range(const kinematics::CablePlotterGeometry& g, int cable, const Box2& end,
                 CableRange& out) {
  const Eigen::Vector2d& anchor = g.anchors_mm[static_cast<std::size_t>(cable)];
  const Box2 from_centre{end.x + (-anchor.x()), end.y + (-anchor.y())};
  const Range d = norm_of(from_centre);
  const double r = g.radius_mm(cable);
  // The solver refuses an end within r (1 + 1e-12) of the centre; keep well clear of it.
  if (!(d.lo > r * (1.0 + 1e-9)) || !(d.lo > 0.0) || !d.known()) return false;
  const Eigen::Vector2d corners[4] = {{from_centre.x.lo, from_centre.y.lo},
                                      {from_centre.x.hi, from_centre.y.lo},
                                      {from_centre.x.hi, from_centre.y.hi},
                                      {from_centre.x.lo, from_centre.y.hi}};
  double raw[4], lifted[4];
  for (int k = 0; k < 4; ++k) raw[k] = cable_direction(cable, corners[k], r);
  lifted[0] = raw[0];
  Range direction = Range::point(raw[0]);
  for (int k = 1; k < 4; ++k) {
    lifted[k] = lifted[k - 1] + turn_between(raw[k - 1], raw[k]);
    direction = {std::min(direction.lo, lifted[k]), std::max(direction.hi, lifted[k])};
  }
  // Around the box and back: no net turn for a box clear of the pulley.
  if (!(std::abs(lifted[3] + turn_between(raw[3], raw[0]) - lifted[0]) < 1e-9)) return false;
  out.gamma = cable == 0 ? direction : -direction;
  out.span_mm = {std::sqrt(d.lo * d.lo - r * r), std::sqrt(d.hi * d.hi - r * r)};
  return true;
}

// Tensions t0 = w sin g1 / sin(g0 + g1), t1 = w sin g0 / sin(g0 + g1) (Cramer's rule on
// t0 u0 + t1 u1 = load). Where both gammas and their sum lie in (0, pi), exactly: t0 rises with
// g1 and, for fixed g1, is w sin g1 / sin(sum), largest at an end of g0's range and least where
// sin(sum) is largest. Elsewhere by interval arithmetic.
std::array<Range, 2> tensions(double w, Range g0, Range g1) {
  const Range sum = g0 + g1;
  const bool inside = g0.lo > 0.0 && g1.lo > 0.0 && sum.lo > 0.0 && sum.hi < kPi;
  if (!inside) return {divided(w * sin_of(g1), sin_of(sum)), divided(w * sin_of(g0), sin_of(sum))};
  const auto one = [&](Range other, Range own_sum_partner) {
    // t = w sin(other) / sin(partner + other), partner the other gamma.
    const auto at = [&](double p, double o) { return w * std::sin(o) / std::sin(p + o); };
    const double hi = std::max(at(own_sum_partner.lo, other.hi), at(own_sum_partner.hi, other.hi));
    const Range sums{own_sum_partner.lo + other.lo, own_sum_partner.hi + other.lo};
    const double lo = w * std::sin(other.lo) / sin_of(sums).hi;
    return Range{lo, hi};
  };
  return {one(g1, g0), one(g0, g1)};
}

double load_N(const kinematics::CablePlotterGeometry& g) {
  return g.effector_mass_kg > 0.0
             ? g.effector_mass_kg * kinematics::kStandardGravity_mm_per_s2 * 1e-3
             : 1.0;
}

// The effector's point b (mm from the pen, level frame) turned by every tilt of `tilt`.
Box2 turned(const Eigen::Vector2d& b, Range tilt) {
  if (tilt.lo == 0.0 && tilt.hi == 0.0) return {Range::point(b.x()), Range::point(b.y())};
  const Range c = cos_of(tilt), s = sin_of(tilt);
  return {c * Range::point(b.x()) - s * Range::point(b.y()),
          s * Range::point(b.x()) + c * Range::point(b.y())};
}

// Both cables over the pen box and tilt range; false where an end may reach its pulley.
bool cables_at(const kinematics::CablePlotterGeometry& g, const Box2& pen, Range tilt,
               std::array<CableRange, 2>& cables) {
  for (int cable = 0; cable < 2; ++cable) {
    const Box2 arm = turned(g.attach_mm[static_cast<std::size_t>(cable)], tilt);
    if (!cable_range(g, cable, {pen.x + arm.x, pen.y + arm.y}, cables[cable])) return false;
  }
  return true;
}

// The moment about the pen (N mm, counter-clockwise) times sin(gamma0 + gamma1), over the pen
// box and a tilt range: cross(R c, load) - sum t_i cross(R a_i, u_i), load (0, -w),
// u_i = (sin b, -cos b) with b = gamma0 and -gamma1 the cables' directions from straight down,
// and t_i sin(sum) = w sin(the other gamma) by the law of sines. The factor keeps the value
// bounded where the cables come into line (the tensions grow without bound there); it vanishes
// where the moment does, and where the cables are in line, which only adds tilts to keep.
// Unknown where a cable's end may touch its pulley.
Range scaled_moment_range(const kinematics::CablePlotterGeometry& g, const Box2& pen, Range tilt) {
  std::array<CableRange, 2> cables;
  if (!cables_at(g, pen, tilt, cables)) return {};
  const double w = load_N(g);
  const Range sum = cables[0].gamma + cables[1].gamma;
  Range moment = (-w * turned(g.center_of_mass_mm, tilt).x) * sin_of(sum);
  for (int cable = 0; cable < 2; ++cable) {
    const Box2 arm = turned(g.attach_mm[static_cast<std::size_t>(cable)], tilt);
    const Range b = cable == 0 ? cables[0].gamma : -cables[1].gamma;
    const Range arm_cross_u = arm.x * (-cos_of(b)) - arm.y * sin_of(b);
    const Range scaled_tension = w * sin_of(cables[static_cast<std::size_t>(1 - cable)].gamma);
    moment = moment - scaled_tension * arm_cross_u;
  }
  return moment;
}

// The first (from_low) or last tilt of the search range where the moment may vanish: a depth-
// first search that drops every tilt range over which the moment provably keeps one sign.
// NaN where none may.
double tilt_end(const kinematics::CablePlotterGeometry& g, const Box2& pen, bool from_low) {
  struct Span {
    double lo, hi;
  };
  std::array<Span, 64> stack;
  int size = 0;
  stack[static_cast<std::size_t>(size++)] = {-kTiltSearch_rad, kTiltSearch_rad};
  while (size > 0) {
    const Span span = stack[static_cast<std::size_t>(--size)];
    const Range moment = scaled_moment_range(g, pen, {span.lo, span.hi});
    if (moment.lo > 0.0 || moment.hi < 0.0) continue;
    if (span.hi - span.lo <= kTiltLeaf_rad || size + 2 > static_cast<int>(stack.size())) {
      return from_low ? span.lo : span.hi;
    }
    const double middle = 0.5 * (span.lo + span.hi);
    const Span low{span.lo, middle}, high{middle, span.hi};
    // The side searched first goes on the stack last.
    stack[static_cast<std::size_t>(size++)] = from_low ? high : low;
    stack[static_cast<std::size_t>(size++)] = from_low ? low : high;
  }
  return NAN;
}

// Each cable's joint: its arc on the pulley from the top point, r (pi/2 - gamma), and its span,
// each stretched by 1 + c T (the arc by the tension where it is positive), plus its offset.
Range joint_range(const kinematics::CablePlotterGeometry& g, int cable, const CableRange& c,
                  Range tension) {
  if (!(c.gamma.lo >= -0.5 * kPi && c.gamma.hi < 1.5 * kPi)) return {};
  const Range arc = g.radius_mm(cable) * (-c.gamma + 0.5 * kPi);
  const double compliance = g.compliance_per_N();
  if (compliance == 0.0)
    return arc + c.span_mm + g.cable_offsets_mm[static_cast<std::size_t>(cable)];
  const Range stretch = compliance * tension + 1.0;
  const Range pulled{std::max(0.0, tension.lo), std::max(0.0, tension.hi)};
  return divided(arc, compliance * pulled + 1.0) + divided(c.span_mm, stretch) +
         g.cable_offsets_mm[static_cast<std::size_t>(cable)];
}

// The tensions' derivatives in the pen position, enclosed over the pen box and tilt range.
// With t_i = f_i(gamma0, gamma1) (tensions()) and each gamma turning at n / s per mm of its
// cable's end (n the unit normal of the cable, s its span), the effector's tilt phi adds
// d(gamma_i)/d(phi) d(phi)/dp, d(phi)/dp = -M_p / M_phi by the implicit function theorem on the
// moment M (scaled_moment_range), M_phi kept away from zero. Rows: cables; columns: x, y.
struct TensionGradient {
  bool known = false;
  std::array<std::array<Range, 2>, 2> d;  // d[cable][axis], N/mm
};

TensionGradient tension_gradient(const kinematics::CablePlotterGeometry& g, Range tilt,
                                 const std::array<CableRange, 2>& cables) {
  TensionGradient out;
  const double w = load_N(g);
  const Range g0 = cables[0].gamma, g1 = cables[1].gamma, sum = g0 + g1;
  if (!(g0.lo > 0.0 && g1.lo > 0.0 && sum.lo > 0.0 && sum.hi < kPi)) return out;
  const Range sin_sum = sin_of(sum), cos_sum = cos_of(sum);
  const Range sin_squared = sin_sum * sin_sum;
  // df[i][j] = d t_i / d gamma_j.
  const Range t0 = divided(w * sin_of(g1), sin_sum), t1 = divided(w * sin_of(g0), sin_sum);
  const std::array<std::array<Range, 2>, 2> df{
      {{divided(-w * (sin_of(g1) * cos_sum), sin_squared), divided(w * sin_of(g0), sin_squared)},
       {divided(w * sin_of(g1), sin_squared), divided(-w * (sin_of(g0) * cos_sum), sin_squared)}}};
  const std::array<Range, 2> t{t0, t1};
  // Per cable: beta (its direction from straight down), its end's gradient of gamma, the arm.
  std::array<std::array<Range, 2>, 2> grad_gamma;  // [cable][axis]
  std::array<Range, 2> x_arm, y_arm, gamma_tilt;  // cross(R a, u), its beta-derivative, dgamma/dphi
  for (int c = 0; c < 2; ++c) {
    const auto k = static_cast<std::size_t>(c);
    const double sign = c == 0 ? 1.0 : -1.0;  // beta0 = gamma0, beta1 = -gamma1
    const Range beta = sign * cables[k].gamma;
    const Range cb = cos_of(beta), sb = sin_of(beta);
    const Range inverse_span = divided(Range::point(1.0), cables[k].span_mm);
    grad_gamma[k] = {sign * (cb * inverse_span), sign * (sb * inverse_span)};
    const Box2 arm = turned(g.attach_mm[k], tilt);
    x_arm[k] = arm.x * (-cb) - arm.y * sb;
    y_arm[k] = sign * (arm.x * sb - arm.y * cb);  // d X / d gamma
    // The end moves by (-A.y, A.x) per rad of tilt.
    gamma_tilt[k] = grad_gamma[k][0] * (-arm.y) + grad_gamma[k][1] * arm.x;
  }
  std::array<Range, 2> tilt_slope{Range::point(0.0), Range::point(0.0)};  // d phi / d p
  if (g.tilts()) {
    const Box2 com = turned(g.center_of_mass_mm, tilt);
    // M_phi: the centre of mass's turn, the tensions' change with the gammas, the arms' turn.
    Range m_phi = w * com.y;
    for (std::size_t c = 0; c < 2; ++c) {
      const Range dt = df[c][0] * gamma_tilt[0] + df[c][1] * gamma_tilt[1];
      const Box2 arm = turned(g.attach_mm[c], tilt);
      const double sign = c == 0 ? 1.0 : -1.0;
      const Range beta = sign * cables[c].gamma;
      const Range x_turn = arm.y * cos_of(beta) - arm.x * sin_of(beta);  // dX/dphi at fixed beta
      m_phi = m_phi - (dt * x_arm[c] + t[c] * (y_arm[c] * gamma_tilt[c] + x_turn));
    }
    if (!(m_phi.hi < 0.0) && !(m_phi.lo > 0.0)) return out;
    for (std::size_t axis = 0; axis < 2; ++axis) {
      Range m_p = Range::point(0.0);
      for (std::size_t c = 0; c < 2; ++c) {
        const Range dt = df[c][0] * grad_gamma[0][axis] + df[c][1] * grad_gamma[1][axis];
        m_p = m_p - (dt * x_arm[c] + t[c] * (y_arm[c] * grad_gamma[c][axis]));
      }
      tilt_slope[axis] = -divided(m_p, m_phi);
    }
  }
  for (std::size_t c = 0; c < 2; ++c) {
    for (std::size_t axis = 0; axis < 2; ++axis) {
      const Range d0 = grad_gamma[0][axis] + gamma_tilt[0] * tilt_slope[axis];
      const Range d1 = grad_gamma[1][axis] + gamma_tilt[1] * tilt_slope[axis];
      out.d[c][axis] = df[c][0] * d0 + df[c][1] * d1;
    }
  }
  out.known =
      out.d[0][0].known() && out.d[0][1].known() && out.d[1][0].known() && out.d[1][1].known();
  return out;
}

// Intersects each tension's range with the mean-value form about the box's middle:
// t(c) + sum_k dt/dp_k (p_k - c_k), over the segment c +- s `half_chord` (s in [-1, 1]) where
// given (the directional derivative there is small where a tension turns along a move: the
// bound is then of second order in the piece), else over the box. t(c) from the statics.
void tighten_by_mean_value(const kinematics::CablePlotterGeometry& g, const Eigen::Vector2d& centre,
                           const Box2& pen, const Eigen::Vector2d* half_chord,
                           const TensionGradient& gradient, CableBoxBound& out) {
  if (!gradient.known || !(g.effector_mass_kg > 0.0)) return;
  kinematics::CableBalance balance;
  const Eigen::Vector2d gravity(0.0, -kinematics::kStandardGravity_mm_per_s2);
  if (!kinematics::solve_cable_balance(g, centre, gravity, balance).ok()) return;
  for (std::size_t c = 0; c < 2; ++c) {
    const double at_centre = balance.statics.tension_N[c];
    if (!holds_value(out.tension_N[c], at_centre)) continue;  // the centre's balance is another
    Range change;
    if (half_chord != nullptr) {
      change = Range{-1.0, 1.0} *
               (gradient.d[c][0] * half_chord->x() + gradient.d[c][1] * half_chord->y());
    } else {
      change = gradient.d[c][0] * Range{pen.x.lo - centre.x(), pen.x.hi - centre.x()} +
               gradient.d[c][1] * Range{pen.y.lo - centre.y(), pen.y.hi - centre.y()};
    }
    // The change widened as every bound is; the centre's tension by a few units in the last
    // place only (the tilt's Newton iteration ends at rounding level), so that the bound shrinks
    // with the piece instead of stopping at a floor near a limit.
    const double ulps = 16.0 * std::numeric_limits<double>::epsilon() * std::abs(at_centre);
    const Range mean_value = widened(change) + Range{at_centre - ulps, at_centre + ulps};
    out.tension_N[c] = {std::max(out.tension_N[c].lo, mean_value.lo),
                        std::min(out.tension_N[c].hi, mean_value.hi)};
  }
}

}  // namespace

std::string cable_bound_unavailable(const kinematics::CablePlotterGeometry& geometry) {
  if (geometry.cable_density_kg_per_m > 0.0) {
    return "no bound on the balance of cables that sag (cable_density > 0) here: the catenary's "
           "tensions and lengths are solved by Newton's method, and no bound on how far they lie "
           "from the straight cables' is derived";
  }
  if (geometry.spool_buildup_mm_per_m > 0.0) {
    return "no bound on the joints of cables that build up on their drums (spool_buildup) here";
  }
  return {};
}

CableBoxBound cable_box_bound(const kinematics::CablePlotterGeometry& g,
                              const Eigen::Vector2d& centre_mm, const Eigen::Vector2d& half_mm,
                              const Eigen::Vector2d* half_chord_mm) {
  CableBoxBound out;
  if (!cable_bound_unavailable(g).empty()) return out;
  const Box2 pen{{centre_mm.x() - half_mm.x(), centre_mm.x() + half_mm.x()},
                 {centre_mm.y() - half_mm.y(), centre_mm.y() + half_mm.y()}};
  Range tilt = Range::point(0.0);
  if (g.tilts()) {
    tilt = {tilt_end(g, pen, true), tilt_end(g, pen, false)};
    if (!(tilt.lo <= tilt.hi)) {
      // Every tilt's moment keeps one sign (an undefined one is kept as a possible root).
      out.no_balance = true;
      return out;
    }
    tilt = {tilt.lo - 1e-11, tilt.hi + 1e-11};  // the solver's own tolerance
  }
  std::array<CableRange, 2> cables;
  if (!cables_at(g, pen, tilt, cables)) return out;
  out.known = true;
  out.tilt_rad = tilt;
  const std::array<Range, 2> t = tensions(load_N(g), cables[0].gamma, cables[1].gamma);
  out.apart = widened(abs_of(sin_of(cables[0].gamma + cables[1].gamma)) + (-1e-12));
  for (std::size_t c = 0; c < 2; ++c) {
    // 1 / t_c = sin(sum) / (w sin(the other gamma)): smooth where the cables come into line.
    out.inverse_tension_per_N[c] = widened(divided(sin_of(cables[0].gamma + cables[1].gamma),
                                                   load_N(g) * sin_of(cables[1 - c].gamma)));
  }
  const bool massless = !(g.effector_mass_kg > 0.0);
  for (int cable = 0; cable < 2; ++cable) {
    const auto k = static_cast<std::size_t>(cable);
    out.tension_N[k] = widened(t[k]);
    out.joint_mm[k] =
        widened(joint_range(g, cable, cables[k], massless ? Range::point(0.0) : out.tension_N[k]));
  }
  // The mean-value form costs a balance at the middle: only where the box's ranges decide
  // nothing about a tension's sign or limits.
  const auto decided = [&](const Range& tension) {
    const auto clear_of = [&](double limit) { return tension.lo > limit || tension.hi < limit; };
    return clear_of(0.0) &&
           (!g.tension_limited || (clear_of(g.tension_min_N) && clear_of(g.tension_max_N)));
  };
  if (!decided(out.tension_N[0]) || !decided(out.tension_N[1])) {
    tighten_by_mean_value(g, centre_mm, pen, half_chord_mm, tension_gradient(g, tilt, cables), out);
  }
  return out;
}

}  // namespace pkm::bounds

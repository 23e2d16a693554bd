#include "rrf.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>
#include <stdexcept>
#include <vector>

namespace pkm::test::rrf_reference {
namespace {

constexpr double kPi = 3.14159265358979323846;
double radians(double degrees) {
  return degrees * kPi / 180.0;
}

std::vector<double> colon_list(const std::string& text) {
  std::vector<double> values;
  std::stringstream stream(text);
  std::string item;
  while (std::getline(stream, item, ':')) values.push_back(std::stod(item));
  return values;
}

void apply(LinearDelta& delta, const std::string& code, char letter, const std::string& value) {
  const std::string key = code + " " + letter;
  if (code == "M665" && letter == 'L') {
    const std::vector<double> rods = colon_list(value);
    for (std::size_t k = 0; k < 3; ++k) delta.diagonals[k] = k < rods.size() ? rods[k] : rods[0];
    return;
  }
  const double number = std::stod(value);
  if (code == "M665") {
    if (letter == 'R') delta.radius = number;
    if (letter == 'H') delta.homed_height = number;
    if (letter == 'B') delta.print_radius = number;
    if (letter == 'X') delta.angle_corrections[0] = number;
    if (letter == 'Y') delta.angle_corrections[1] = number;
    if (letter == 'Z') delta.angle_corrections[2] = number;
  } else if (code == "M666") {
    if (letter == 'X') delta.endstop_adjustments[0] = number;
    if (letter == 'Y') delta.endstop_adjustments[1] = number;
    if (letter == 'Z') delta.endstop_adjustments[2] = number;
    if (letter == 'A') delta.x_tilt = number * 0.01;
    if (letter == 'B') delta.y_tilt = number * 0.01;
  }
  delta.settings[key] = number;
}

// "; drive Y = tower B = joint 3 ..." names joint 3 (from 1) for drive Y.
void read_drive_comment(std::array<int, 3>& joint_of_drive, const std::string& comment) {
  std::istringstream words(comment);
  std::string semicolon, drive_word, drive, eq1, tower_word, tower, eq2, joint_word;
  int joint = 0;
  words >> semicolon >> drive_word >> drive >> eq1 >> tower_word >> tower >> eq2 >> joint_word >>
      joint;
  if (drive_word != "drive" || joint_word != "joint" || drive.size() != 1) return;
  const int index = drive[0] - 'X';
  if (index >= 0 && index < 3) joint_of_drive[static_cast<std::size_t>(index)] = joint - 1;
}

void apply_rotary(RotaryDelta& delta, const std::string& code, char letter,
                  const std::string& value) {
  if (code == "M669" && (letter == 'U' || letter == 'L' || letter == 'H')) {
    const std::vector<double> values = colon_list(value);
    std::array<double, 3>& target = letter == 'U'   ? delta.arms
                                    : letter == 'L' ? delta.rods
                                                    : delta.bearing_heights;
    for (std::size_t k = 0; k < 3; ++k) target[k] = values.size() == 1 ? values[0] : values.at(k);
    return;
  }
  if (code == "M669" && letter == 'A') {
    const std::vector<double> values = colon_list(value);
    delta.min_arm_angle = values.at(0);
    delta.max_arm_angle = values.at(1);
    return;
  }
  if (code == "M208" && letter == 'Z') {
    const std::vector<double> values = colon_list(value);
    delta.settings["M208 Z min"] = values.front();
    delta.settings["M208 Z max"] = values.back();
    return;
  }
  const double number = std::stod(value);
  const int drive = letter - 'X';
  if (code == "M669" && letter == 'R') delta.radius = number;
  if (code == "M669" && drive >= 0 && drive < 3) {
    delta.angle_corrections[static_cast<std::size_t>(drive)] = number;
  }
  if (code == "M666" && drive >= 0 && drive < 3) {
    delta.endstop_adjustments[static_cast<std::size_t>(drive)] = number;
  }
  delta.settings[code + " " + letter] = number;
}

}  // namespace

RotaryDelta parse_rotary(const std::string& config_text) {
  RotaryDelta delta;
  std::istringstream lines(config_text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("; drive ", 0) == 0) read_drive_comment(delta.joint_of_drive, line);
    std::istringstream words(line.substr(0, line.find(';')));
    std::string code, word;
    if (!(words >> code)) continue;
    while (words >> word) apply_rotary(delta, code, word[0], word.substr(1));
  }
  return delta;
}

// Arm A, B, C point at -150, -30, 90 deg plus their corrections; in the arm's frame (+x along
// the arm) the rod from the elbow (R + U cos t, 0, H + U sin t) reaches the head (x, y, z):
// L^2 = (U cos t + R - x)^2 + y^2 + (U sin t + H - z)^2, i.e. a cos t + b sin t = c; RRF takes
// the lower root for sin t.
double arm_angle_deg(const RotaryDelta& delta, int arm, double x, double y, double z) {
  const std::size_t k = static_cast<std::size_t>(arm);
  const double nominal[3] = {-150.0, -30.0, 90.0};
  const double angle = radians(nominal[k] + delta.angle_corrections[k]);
  const double along = x * std::cos(angle) + y * std::sin(angle);
  const double across = y * std::cos(angle) - x * std::sin(angle);
  const double u = delta.arms[k];
  const double r_minus_x = delta.radius - along;
  const double h_minus_z = delta.bearing_heights[k] - z;
  const double a = 2.0 * u * r_minus_x;
  const double b = 2.0 * u * h_minus_z;
  const double c = delta.rods[k] * delta.rods[k] - u * u -
                   (h_minus_z * h_minus_z + r_minus_x * r_minus_x + across * across);
  const double sin_t = (b * c - a * std::sqrt(a * a + b * b - c * c)) / (a * a + b * b);
  return std::asin(sin_t) * 180.0 / kPi;
}

double homed_arm_angle_deg(const RotaryDelta& delta, int arm) {
  return delta.max_arm_angle + delta.endstop_adjustments[static_cast<std::size_t>(arm)];
}

LinearDelta parse(const std::string& config_text) {
  LinearDelta delta;
  std::istringstream lines(config_text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.rfind("; drive ", 0) == 0) read_drive_comment(delta.joint_of_drive, line);
    const std::string code_part = line.substr(0, line.find(';'));
    std::istringstream words(code_part);
    std::string code, word;
    if (!(words >> code)) continue;
    while (words >> word) apply(delta, code, word[0], word.substr(1));
  }
  return delta;
}

std::array<double, 2> tower_position(const LinearDelta& delta, int tower) {
  const double r = delta.radius;
  const std::array<double, 3>& c = delta.angle_corrections;
  switch (tower) {
    case 0:
      return {-r * std::cos(radians(30.0 + c[0])), -r * std::sin(radians(30.0 + c[0]))};
    case 1:
      return {r * std::cos(radians(30.0 - c[1])), -r * std::sin(radians(30.0 - c[1]))};
    case 2:
      return {-r * std::sin(radians(c[2])), r * std::cos(radians(c[2]))};
    default:
      throw std::out_of_range("tower");
  }
}

double motor_position(const LinearDelta& delta, int tower, double x, double y, double z) {
  const std::array<double, 2> at = tower_position(delta, tower);
  const double rod = delta.diagonals[static_cast<std::size_t>(tower)];
  return std::sqrt(rod * rod - (x - at[0]) * (x - at[0]) - (y - at[1]) * (y - at[1])) + z +
         x * delta.x_tilt + y * delta.y_tilt;
}

double homed_carriage_height(const LinearDelta& delta, int tower) {
  const double rod = delta.diagonals[static_cast<std::size_t>(tower)];
  return delta.homed_height + std::sqrt(rod * rod - delta.radius * delta.radius) +
         delta.endstop_adjustments[static_cast<std::size_t>(tower)];
}

Hangprinter parse_hangprinter(const std::string& config_text) {
  Hangprinter hangprinter;
  const std::string letters = "ABCDI";
  std::size_t count = 4;
  std::vector<std::array<double, 3>> anchors(5, {0.0, 0.0, 0.0});
  std::map<char, std::vector<double>> arrays;  // M666 R U O L H J I X Y as given
  std::istringstream lines(config_text);
  std::string line;
  while (std::getline(lines, line)) {
    std::istringstream words(line.substr(0, line.find(';')));
    std::string code, word;
    if (!(words >> code)) continue;
    while (words >> word) {
      const char letter = word[0];
      const std::string value = word.substr(1);
      if (code == "M669" && letter == 'N') count = static_cast<std::size_t>(std::stoi(value));
      const std::size_t anchor = letters.find(letter);
      if (code == "M669" && anchor != std::string::npos) {
        const std::vector<double> xyz = colon_list(value);
        if (xyz.size() != 3) throw std::runtime_error("M669 " + word + ": 3 values expected");
        anchors[anchor] = {xyz[0], xyz[1], xyz[2]};
      }
      if (code != "M666") continue;
      if (letter == 'Q') hangprinter.spool_buildup = std::stod(value);
      if (letter == 'F') hangprinter.flex = std::stoi(value);
      if (letter == 'W') hangprinter.mover_weight = std::stod(value);
      if (letter == 'S') hangprinter.spring_k_per_unit_length = std::stod(value);
      if (std::string("RUOLHJIXY").find(letter) != std::string::npos) {
        arrays[letter] = colon_list(value);
      }
    }
  }
  anchors.resize(count);
  hangprinter.anchors = anchors;
  // RRF's Init defaults for what config.g does not set.
  const std::map<char, std::vector<double>> defaults = {
      {'R', {75, 75, 75, 75, 75}}, {'U', {2, 2, 2, 2, 4}},           {'O', {1, 1, 1, 1, 1}},
      {'L', {20, 20, 20, 20, 20}}, {'H', {255, 255, 255, 255, 255}}, {'J', {25, 25, 25, 25, 25}},
      {'I', {0, 0, 0, 0, 0}},      {'X', {70, 70, 70, 70, 70}},      {'Y', {0, 0, 0, 0, 0}}};
  for (const auto& [letter, values] : defaults) {
    std::vector<double> chosen = values;
    chosen.resize(count);
    if (arrays.count(letter)) chosen = arrays[letter];
    if (chosen.size() != count) throw std::runtime_error(std::string("M666 ") + letter + ": count");
    hangprinter.per_anchor[letter] = chosen;
  }
  return hangprinter;
}

namespace {

double distance(const std::array<double, 3>& a, double x, double y, double z) {
  return std::sqrt((a[0] - x) * (a[0] - x) + (a[1] - y) * (a[1] - y) + (a[2] - z) * (a[2] - z));
}

// Solves m v = r by Gaussian elimination with partial pivoting (m square); false if singular.
bool gauss_solve(std::vector<std::vector<double>> m, std::vector<double> r,
                 std::vector<double>& v) {
  const std::size_t n = r.size();
  for (std::size_t c = 0; c < n; ++c) {
    std::size_t pivot = c;
    for (std::size_t i = c + 1; i < n; ++i) {
      if (std::abs(m[i][c]) > std::abs(m[pivot][c])) pivot = i;
    }
    if (std::abs(m[pivot][c]) < 1e-300) return false;
    std::swap(m[c], m[pivot]);
    std::swap(r[c], r[pivot]);
    for (std::size_t i = c + 1; i < n; ++i) {
      const double factor = m[i][c] / m[c][c];
      for (std::size_t j = c; j < n; ++j) m[i][j] -= factor * m[c][j];
      r[i] -= factor * r[c];
    }
  }
  v.assign(n, 0.0);
  for (std::size_t i = n; i-- > 0;) {
    double sum = r[i];
    for (std::size_t j = i + 1; j < n; ++j) sum -= m[i][j] * v[j];
    v[i] = sum / m[i][i];
  }
  return true;
}

}  // namespace

std::vector<double> hangprinter_forces(const Hangprinter& hp, double x, double y, double z) {
  // StaticForcesQp: minimise |A t - (0, 0, W g)|^2 + 0.001 |t|^2 over I <= t <= X, A's columns the
  // unit vectors to the anchors. Here by trying every assignment of each force to free, its lower
  // or its upper limit, and keeping the one whose solution meets the optimality conditions.
  const std::size_t n = hp.anchors.size();
  std::vector<std::array<double, 3>> unit(n);
  for (std::size_t i = 0; i < n; ++i) {
    const double d = distance(hp.anchors[i], x, y, z);
    const std::array<double, 3>& a = hp.anchors[i];
    unit[i] = {(a[0] - x) / d, (a[1] - y) / d, (a[2] - z) / d};
  }
  const double weight = hp.mover_weight * 9.81;
  std::vector<std::vector<double>> h(n, std::vector<double>(n));
  std::vector<double> f(n);
  for (std::size_t i = 0; i < n; ++i) {
    f[i] = unit[i][2] * weight;
    for (std::size_t j = 0; j < n; ++j) {
      h[i][j] = unit[i][0] * unit[j][0] + unit[i][1] * unit[j][1] + unit[i][2] * unit[j][2] +
                (i == j ? 0.001 : 0.0);
    }
  }
  const std::vector<double>& low = hp.per_anchor.at('I');
  const std::vector<double>& high = hp.per_anchor.at('X');
  std::size_t states = 1;
  for (std::size_t i = 0; i < n; ++i) states *= 3;
  for (std::size_t code = 0; code < states; ++code) {
    std::vector<int> state(n);  // 0 free, 1 at low, 2 at high
    std::vector<double> t(n, 0.0);
    std::vector<std::size_t> free;
    for (std::size_t i = 0, c = code; i < n; ++i, c /= 3) {
      state[i] = static_cast<int>(c % 3);
      if (state[i] == 0) free.push_back(i);
      if (state[i] == 1) t[i] = low[i];
      if (state[i] == 2) t[i] = high[i];
    }
    std::vector<std::vector<double>> m(free.size(), std::vector<double>(free.size()));
    std::vector<double> r(free.size()), v;
    for (std::size_t a = 0; a < free.size(); ++a) {
      r[a] = f[free[a]];
      for (std::size_t j = 0; j < n; ++j) {
        if (state[j] != 0) r[a] -= h[free[a]][j] * t[j];
      }
      for (std::size_t b = 0; b < free.size(); ++b) m[a][b] = h[free[a]][free[b]];
    }
    if (!gauss_solve(m, r, v)) continue;
    for (std::size_t a = 0; a < free.size(); ++a) t[free[a]] = v[a];
    bool optimal = true;
    for (std::size_t i = 0; i < n && optimal; ++i) {
      double gradient = -f[i];
      for (std::size_t j = 0; j < n; ++j) gradient += h[i][j] * t[j];
      if (state[i] == 0) optimal = t[i] >= low[i] - 1e-12 && t[i] <= high[i] + 1e-12;
      if (state[i] == 1) optimal = gradient >= -1e-12;
      if (state[i] == 2) optimal = gradient <= 1e-12;
    }
    if (optimal) return t;
  }
  throw std::runtime_error("no optimal forces found");
}

std::vector<double> hangprinter_forces_iterated(const Hangprinter& hp, double x, double y,
                                                double z) {
  // solve_box_ridge_ls as RRF iterates it: the unconstrained ridge solution clamped into [I, X];
  // then, until the projected gradient is within 1e-3 N (a force within 1e-5 N of a limit counting
  // as at it) or after 100 rounds, a Newton step on the forces that are free or pulled inwards by
  // more than 1e-3 N (else the one pulled most), as long as no limit is crossed, then clamped.
  const std::size_t n = hp.anchors.size();
  std::vector<std::vector<double>> h(n, std::vector<double>(n));
  std::vector<double> f(n);
  {
    const double weight = hp.mover_weight * 9.81;
    std::vector<std::array<double, 3>> unit(n);
    for (std::size_t i = 0; i < n; ++i) {
      const double d = distance(hp.anchors[i], x, y, z);
      for (int k = 0; k < 3; ++k) unit[i][k] = (hp.anchors[i][k] - std::array{x, y, z}[k]) / d;
    }
    for (std::size_t i = 0; i < n; ++i) {
      f[i] = unit[i][2] * weight;
      for (std::size_t j = 0; j < n; ++j) {
        h[i][j] = unit[i][0] * unit[j][0] + unit[i][1] * unit[j][1] + unit[i][2] * unit[j][2] +
                  (i == j ? 0.001 : 0.0);
      }
    }
  }
  const std::vector<double>& low = hp.per_anchor.at('I');
  const std::vector<double>& high = hp.per_anchor.at('X');
  const double tol = 1e-3, edge = 1e-5;
  std::vector<double> t;
  gauss_solve(h, f, t);
  for (std::size_t i = 0; i < n; ++i) t[i] = std::min(std::max(t[i], low[i]), high[i]);
  const auto gradient = [&](std::size_t i) {
    double g = -f[i];
    for (std::size_t j = 0; j < n; ++j) g += h[i][j] * t[j];
    return g;
  };
  for (int round = 0; round < 100; ++round) {
    double projected = 0.0;
    std::vector<std::size_t> free;
    for (std::size_t i = 0; i < n; ++i) {
      const double g = gradient(i);
      const bool at_low = t[i] <= low[i] + edge, at_high = t[i] >= high[i] - edge;
      if ((!at_low && !at_high) || (at_low && g < -tol) || (at_high && g > tol)) free.push_back(i);
      if (!((at_low && g > 0.0) || (at_high && g < 0.0))) projected += g * g;
    }
    if (std::sqrt(projected) <= tol) break;
    if (free.empty()) {
      std::size_t best = 0;
      double most = 0.0;
      for (std::size_t i = 0; i < n; ++i) {
        const double g = gradient(i);
        double pull = 0.0;
        if (t[i] <= low[i] + edge) pull = std::max(0.0, -g);
        if (t[i] >= high[i] - edge) pull = std::max(pull, g);
        if (pull > most) {
          most = pull;
          best = i;
        }
      }
      free.push_back(best);
    }
    std::vector<std::vector<double>> m(free.size(), std::vector<double>(free.size()));
    std::vector<double> r(free.size()), step;
    for (std::size_t a = 0; a < free.size(); ++a) {
      r[a] = -gradient(free[a]);
      for (std::size_t b = 0; b < free.size(); ++b) m[a][b] = h[free[a]][free[b]];
    }
    gauss_solve(m, r, step);
    double alpha = 1.0;
    for (std::size_t a = 0; a < free.size(); ++a) {
      const std::size_t i = free[a];
      if (std::abs(step[a]) < 1e-8) continue;
      const double most_alpha =
          step[a] > 0.0 ? (high[i] - t[i]) / step[a] : (low[i] - t[i]) / step[a];
      if (most_alpha < alpha) alpha = std::max(0.0, most_alpha);
    }
    for (std::size_t a = 0; a < free.size(); ++a) t[free[a]] += alpha * step[a];
    for (std::size_t i = 0; i < n; ++i) t[i] = std::min(std::max(t[i], low[i]), high[i]);
  }
  return t;
}

double hangprinter_motor_steps(const Hangprinter& hp, int anchor, double x, double y, double z) {
  const std::size_t i = static_cast<std::size_t>(anchor);
  const std::array<double, 3>& a = hp.anchors.at(i);
  const double d = distance(a, x, y, z);
  double line_position = d - distance(a, 0.0, 0.0, 0.0);
  const double u = hp.per_anchor.at('U')[i];
  if (hp.flex == 1) {
    // FlexDistances: minus the force over SpringK(d U + Y) U.
    const double spring = hp.spring_k_per_unit_length / (d * u + hp.per_anchor.at('Y')[i]);
    line_position -= hangprinter_forces_iterated(hp, x, y, z)[i] / (spring * u);
  } else if (hp.flex != 0) {
    throw std::runtime_error("M666 F2 not written here");
  }
  const double radius = hp.per_anchor.at('R')[i];
  const double k2 = -u * hp.per_anchor.at('O')[i] * hp.spool_buildup;
  if (std::abs(k2) <= 1e-9) return line_position * hangprinter_steps_per_mm(hp, anchor);
  const double k0 = 2.0 * hangprinter_steps_per_mm(hp, anchor) * radius / k2;
  return k0 * (std::sqrt(radius * radius + line_position * k2) - radius);
}

double hangprinter_steps_per_mm(const Hangprinter& hp, int anchor) {
  const std::size_t i = static_cast<std::size_t>(anchor);
  const double pi = 3.14159265358979323846;
  return hp.per_anchor.at('U')[i] * hp.per_anchor.at('J')[i] * hp.per_anchor.at('H')[i] /
         (2.0 * pi * hp.per_anchor.at('L')[i]) / hp.per_anchor.at('R')[i];
}

double hangprinter_line_position(const Hangprinter& hangprinter, int anchor, double x, double y,
                                 double z) {
  return hangprinter_motor_steps(hangprinter, anchor, x, y, z) /
         hangprinter_steps_per_mm(hangprinter, anchor);
}

}  // namespace pkm::test::rrf_reference

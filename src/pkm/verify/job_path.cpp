#include "pkm/verify/job_path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <utility>

#include "pkm/gcode/machine_commands.hpp"

namespace pkm::verify {

namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kNoLengthMm = 1e-9;          // a move shorter than this has no controlled path
constexpr double kNearestPrecisionMm = 1e-8;  // where the search along a curved move stops

// Arcs whose controlled path is a circle (or a spiral of slowly changing radius): both in-plane
// axes controlled, and no controlled motion along the normal.
bool planar_in_controlled(const JobPiece& piece) {
  const motion::Segment& s = piece.segment;
  return piece.mask[s.first_axis] != 0.0 && piece.mask[s.second_axis] != 0.0 &&
         (piece.mask[s.normal_axis] == 0.0 || s.start[s.normal_axis] == s.end[s.normal_axis]);
}

double radius_at(const motion::Segment& s, const geometry::Vector6d& p) {
  return std::hypot(p[s.first_axis] - s.centre[s.first_axis],
                    p[s.second_axis] - s.centre[s.second_axis]);
}

Nearest nearest_on_line(const JobPiece& piece, const Eigen::Vector3d& point, double u0, double u1) {
  const Eigen::Vector3d a = piece.point(u0), b = piece.point(u1);
  const Eigen::Vector3d ab = b - a;
  const double squared = ab.squaredNorm();
  const double t = squared > 0.0 ? std::clamp((point - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
  return {(a + t * ab - point).norm(), u0 + t * (u1 - u0)};
}

Nearest nearer(const JobPiece& piece, const Eigen::Vector3d& point, Nearest best, double u) {
  const double distance = (piece.point(u) - point).norm();
  return distance < best.distance_mm ? Nearest{distance, u} : best;
}

// A circle in the controlled coordinates: the nearest points are where the radius through
// `point` meets it (once per turn), or an end of the range.
Nearest nearest_on_planar_arc(const JobPiece& piece, const Eigen::Vector3d& point, double u0,
                              double u1) {
  const motion::Segment& s = piece.segment;
  const int a = s.first_axis, b = s.second_axis;
  Nearest best = nearer(piece, point, {INFINITY, u0}, u0);
  best = nearer(piece, point, best, u1);
  const double start_angle = std::atan2(s.start[b] - s.centre[b], s.start[a] - s.centre[a]);
  const double angle = std::atan2(point[b] - s.centre[b], point[a] - s.centre[a]);
  const double period = kTwoPi / std::abs(s.sweep_rad);
  const double base = (angle - start_angle) / s.sweep_rad;
  for (double u = base + period * std::ceil((u0 - base) / period); u <= u1; u += period) {
    best = nearer(piece, point, best, u);
  }
  return best;
}

// Any other curved move (helices, arcs seen edge-on): coarse samples, then a golden-section
// search about the nearest.
Nearest nearest_by_search(const JobPiece& piece, const Eigen::Vector3d& point, double u0,
                          double u1) {
  const double sweep = std::abs(piece.segment.sweep_rad) * (u1 - u0);
  const int coarse = std::clamp(static_cast<int>(std::ceil(sweep / (kTwoPi / 72.0))), 4, 512);
  Nearest best{INFINITY, u0};
  for (int k = 0; k <= coarse; ++k) best = nearer(piece, point, best, u0 + (u1 - u0) * k / coarse);
  const double step = (u1 - u0) / coarse;
  double lo = std::max(u0, best.u - step), hi = std::min(u1, best.u + step);
  constexpr double kGolden = 0.6180339887498949;
  const double length = std::max(piece.length_mm, piece.segment.length());
  for (int i = 0; i < 100 && (hi - lo) * length > kNearestPrecisionMm; ++i) {
    const double left = hi - kGolden * (hi - lo), right = lo + kGolden * (hi - lo);
    if ((piece.point(left) - point).norm() < (piece.point(right) - point).norm()) {
      hi = right;
    } else {
      lo = left;
    }
  }
  return nearer(piece, point, best, 0.5 * (lo + hi));
}

}  // namespace

Eigen::Vector3d position_mask(const machine::Machine& machine) {
  const geometry::Dof dof = machine.kinematics().dof();
  return {dof.controls(0) ? 1.0 : 0.0, dof.controls(1) ? 1.0 : 0.0, dof.controls(2) ? 1.0 : 0.0};
}

Nearest nearest_on(const JobPiece& piece, const Eigen::Vector3d& point, double u0, double u1) {
  if (piece.segment.kind != motion::SegmentKind::arc) {
    return nearest_on_line(piece, point, u0, u1);
  }
  if (planar_in_controlled(piece)) return nearest_on_planar_arc(piece, point, u0, u1);
  return nearest_by_search(piece, point, u0, u1);
}

JobPath::JobPath(const machine::Machine& machine, const std::filesystem::path& job,
                 const gcode::InterpreterOptions& options, const geometry::Vector6d& origin)
    : file_(job.string()),
      mask_(position_mask(machine)),
      tool_(machine.tool()),
      pen_(machine),
      builder_(machine.home().as_vector(), origin, false),
      interpreter_(job, motion::starting_at(options, machine.home().as_vector(), origin)),
      sink_([this](const gcode::Canon& canon) { take(canon); }) {
  builder_.set_file(file_);
  interpreter_.start(sink_);
}

const JobPiece* JobPath::piece(long index) {
  while (index >= first_index_ + static_cast<long>(window_.size()) && !ended_) {
    if (!interpreter_.step()) ended_ = true;
  }
  if (index < first_index_ || index >= first_index_ + static_cast<long>(window_.size())) {
    return nullptr;
  }
  return &window_[static_cast<std::size_t>(index - first_index_)];
}

void JobPath::forget_before(long index) {
  while (first_index_ < index && !window_.empty()) {
    window_.pop_front();
    ++first_index_;
  }
}

bool compared_command(const std::string& text) {
  const int number = gcode::machine_command_m_number(text);
  return !text.empty() && !(number >= 48 && number <= 53);
}

void JobPath::take(const gcode::Canon& canon) {
  if (canon.kind == gcode::CanonKind::program_end) end_line_ = canon.line;
  if (std::string text = gcode::machine_command_text(canon); compared_command(text)) {
    commands_.push_back({std::move(text), canon.line, end_mm_});
  }
  for (const motion::Segment& segment : builder_.take(canon)) {
    if (segment.kind == motion::SegmentKind::dwell || segment.length() <= 0.0) continue;
    if (tool_.z == machine::ToolZ::pen) pen_.follow(segment);
    window_.push_back(make_piece(segment));
    end_mm_ += window_.back().length_mm;
  }
}

JobPiece JobPath::make_piece(const motion::Segment& segment) const {
  JobPiece piece;
  piece.segment = segment;
  piece.mask = mask_;
  piece.start_mm = end_mm_;
  piece.pen_follows_from = pen_.follows_from();
  if (segment.kind != motion::SegmentKind::arc) {
    piece.length_mm = (piece.point(1.0) - piece.point(0.0)).norm();
  } else {
    const double r0 = radius_at(segment, segment.start), r1 = radius_at(segment, segment.end);
    piece.curvature_per_mm = 1.0 / std::max(std::min(r0, r1), kNoLengthMm);
    if (planar_in_controlled(piece) ||
        (mask_[segment.first_axis] != 0.0 && mask_[segment.second_axis] != 0.0)) {
      const double along = mask_[segment.normal_axis] *
                           (segment.end[segment.normal_axis] - segment.start[segment.normal_axis]);
      piece.length_mm = std::hypot(0.5 * (r0 + r1) * segment.sweep_rad, along);
    } else {
      constexpr int kPoints = 256;  // the controlled path of an arc seen edge-on, as a polyline
      for (int k = 1; k <= kPoints; ++k) {
        piece.length_mm +=
            (piece.point(k / double(kPoints)) - piece.point((k - 1) / double(kPoints))).norm();
      }
    }
  }
  if (piece.length_mm < kNoLengthMm) piece.length_mm = 0.0;
  return piece;
}

}  // namespace pkm::verify

#include "pkm/verify/block_deviation.hpp"

#include <algorithm>
#include <cmath>

namespace pkm::verify {

namespace {
constexpr double kRelativeMargin = 0.004;   // refine until no interval may hide 0.4 % more
constexpr double kAbsoluteMarginMm = 1e-7;  // ... or 1e-7 mm, far below any displayed digit
constexpr int kMaxDepth = 24;               // halvings of a grid interval
// Intervals halved per block at most: the real jobs' posted blocks needed up to 389; a block
// metres long and far from the job (a corrupted program) would otherwise take millions of forward
// kinematics.
constexpr int kMaxHalvings = 2048;
// A block this many times beyond the tolerance fails whatever its exact peak: it is held to the
// estimates of its unrefined intervals from there on.
constexpr double kBeyondTolerance = 100.0;
}  // namespace

BlockMeasure::BlockMeasure(const machine::Machine& machine)
    : machine_(machine), mask_(position_mask(machine)) {}

bool BlockMeasure::add_sample(double lambda, const geometry::Pose& seed) {
  Sample sample;
  sample.lambda = lambda;
  sample.pose = seed;
  const kinematics::JointVector q = q0_ + lambda * (q1_ - q0_);
  if (!machine_.kinematics().forward(q, sample.pose).ok() || !kinematics::all_finite(sample.pose)) {
    return false;
  }
  sample.point = sample.pose.position_mm.cwiseProduct(mask_);
  samples_.push_back(sample);
  return true;
}

bool BlockMeasure::sample_grid(const kinematics::JointVector& q0, const kinematics::JointVector& q1,
                               const geometry::Pose& seed) {
  q0_ = q0;
  q1_ = q1;
  samples_.clear();
  geometry::Pose previous = seed;
  for (int k = 0; k <= kGrid; ++k) {
    if (!add_sample(static_cast<double>(k) / kGrid, previous)) return false;
    previous = samples_.back().pose;
  }
  return true;
}

double BlockMeasure::grid_length_mm() const {
  double length = 0.0;
  for (int k = 1; k <= kGrid; ++k) length += (samples_[k].point - samples_[k - 1].point).norm();
  return length;
}

Eigen::AlignedBox3d BlockMeasure::grid_box(double margin_mm) const {
  Eigen::AlignedBox3d box;
  for (int k = 0; k <= kGrid; ++k) box.extend(samples_[k].point);
  const Eigen::Vector3d margin = Eigen::Vector3d::Constant(margin_mm);
  return {box.min() - margin, box.max() + margin};
}

void BlockMeasure::measure_sample(std::size_t index) {
  Sample& sample = samples_[index];
  const std::size_t ranges = stretch_->size();
  distances_.resize(samples_.size() * ranges);
  sample.distance_mm = INFINITY;
  for (std::size_t i = 0; i < ranges; ++i) {
    const PieceRange& range = (*stretch_)[i];
    const double d = nearest_on(*range.piece, sample.point, range.u0, range.u1).distance_mm;
    distances_[index * ranges + i] = d;
    if (d < sample.distance_mm) {
      sample.distance_mm = d;
      sample.nearest_range = static_cast<int>(i);
    }
  }
}

// Above the largest distance anywhere between samples a and b: the tool path strays from the
// chord a-b by about the middle sample's offset from the chord's middle (exact for a quadratic
// path), and along the chord the distance to one range is at most the larger at its ends (convex
// for a line) plus the range's curvature times the chord squared over 8.
double BlockMeasure::upper_estimate(const Interval& interval) const {
  const Sample &a = samples_[interval.a], &m = samples_[interval.middle], &b = samples_[interval.b];
  const double off_chord = (m.point - 0.5 * (a.point + b.point)).norm();
  const double chord = (b.point - a.point).norm();
  const std::size_t ranges = stretch_->size();
  double along_chord = INFINITY;
  for (std::size_t i = 0; i < ranges; ++i) {
    const double ends =
        std::max(distances_[interval.a * ranges + i], distances_[interval.b * ranges + i]);
    along_chord =
        std::min(along_chord, ends + (*stretch_)[i].piece->curvature_per_mm * chord * chord / 8.0);
  }
  return along_chord + off_chord;
}

bool BlockMeasure::measure(const std::vector<PieceRange>& stretch, double tolerance_mm,
                           BlockDeviation& result) {
  stretch_ = &stretch;
  result = {};
  double largest = 0.0;
  for (std::size_t k = 0; k < samples_.size(); ++k) {
    measure_sample(k);
    largest = std::max(largest, samples_[k].distance_mm);
    if (k > 0) {
      result.sum_of_squares_mm2 += samples_[k].distance_mm * samples_[k].distance_mm;
      ++result.grid_points;
    }
  }
  pending_.clear();
  for (std::size_t k = 0; k + 2 <= static_cast<std::size_t>(kGrid); k += 2) {
    pending_.push_back({k, k + 1, k + 2, 0});
  }
  int halvings = 0;
  double unresolved_mm = 0.0;  // the largest estimate of an interval left unrefined
  std::size_t unresolved_at = 0;
  while (!pending_.empty()) {
    const Interval interval = pending_.back();
    pending_.pop_back();
    const double estimate = upper_estimate(interval);
    if (estimate <= largest * (1.0 + kRelativeMargin) + kAbsoluteMarginMm) continue;
    if (interval.depth >= kMaxDepth || halvings == kMaxHalvings ||
        largest > kBeyondTolerance * tolerance_mm) {
      // Not refined further: the block is held to the estimate there, not to its samples.
      if (estimate > unresolved_mm) {
        unresolved_mm = estimate;
        unresolved_at = interval.middle;
      }
      continue;
    }
    ++halvings;
    const Sample &a = samples_[interval.a], &m = samples_[interval.middle];
    const double left = 0.5 * (a.lambda + m.lambda);
    const double right = 0.5 * (m.lambda + samples_[interval.b].lambda);
    const geometry::Pose left_seed = a.pose, right_seed = m.pose;
    if (!add_sample(left, left_seed) || !add_sample(right, right_seed)) return false;
    const std::size_t l = samples_.size() - 2, r = samples_.size() - 1;
    measure_sample(l);
    measure_sample(r);
    largest = std::max({largest, samples_[l].distance_mm, samples_[r].distance_mm});
    pending_.push_back({interval.a, l, interval.middle, interval.depth + 1});
    pending_.push_back({interval.middle, r, interval.b, interval.depth + 1});
  }
  for (const Sample& sample : samples_) {
    if (sample.distance_mm >= result.max_mm) {
      result.max_mm = sample.distance_mm;
      result.job_line = stretch[static_cast<std::size_t>(sample.nearest_range)].piece->line();
    }
  }
  result.halvings = halvings;
  if (unresolved_mm > result.max_mm) {
    result.max_mm = unresolved_mm;
    const Sample& middle = samples_[unresolved_at];
    result.job_line = stretch[static_cast<std::size_t>(middle.nearest_range)].piece->line();
  }
  return true;
}

}  // namespace pkm::verify

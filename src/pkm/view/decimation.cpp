#include "pkm/view/decimation.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace pkm::view {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// min/max that skip NaN: a bucket without any number stays NaN.
double nan_min(double a, double b) {
  return std::isnan(a) ? b : std::isnan(b) ? a : std::min(a, b);
}
double nan_max(double a, double b) {
  return std::isnan(a) ? b : std::isnan(b) ? a : std::max(a, b);
}
}  // namespace

MinMaxBuckets::MinMaxBuckets(int channels, std::size_t target)
    : channels_(channels),
      target_(std::max<std::size_t>(target, 1)),
      min_(static_cast<std::size_t>(channels)),
      max_(static_cast<std::size_t>(channels)) {}

void MinMaxBuckets::add(double x, std::span<const double> values) {
  if (x_first_.empty() || in_last_ == per_bucket_) {
    if (x_first_.size() == 2 * target_) halve();
  }
  if (x_first_.empty() || in_last_ == per_bucket_) {
    x_first_.push_back(x);
    x_last_.push_back(x);
    for (int c = 0; c < channels_; ++c) {
      min_[c].push_back(kNaN);
      max_[c].push_back(kNaN);
    }
    in_last_ = 0;
  }
  x_last_.back() = x;
  for (int c = 0; c < channels_; ++c) {
    min_[c].back() = nan_min(min_[c].back(), values[static_cast<std::size_t>(c)]);
    max_[c].back() = nan_max(max_[c].back(), values[static_cast<std::size_t>(c)]);
  }
  ++in_last_;
}

// Neighbouring buckets merged in pairs; called only when every bucket is full, so the merged
// ones are full too (the count is even).
void MinMaxBuckets::halve() {
  const std::size_t half = x_first_.size() / 2;
  for (std::size_t i = 0; i < half; ++i) {
    x_first_[i] = x_first_[2 * i];
    x_last_[i] = x_last_[2 * i + 1];
    for (int c = 0; c < channels_; ++c) {
      min_[c][i] = nan_min(min_[c][2 * i], min_[c][2 * i + 1]);
      max_[c][i] = nan_max(max_[c][2 * i], max_[c][2 * i + 1]);
    }
  }
  x_first_.resize(half);
  x_last_.resize(half);
  for (int c = 0; c < channels_; ++c) {
    min_[c].resize(half);
    max_[c].resize(half);
  }
  per_bucket_ *= 2;
  in_last_ = per_bucket_;
}

PathThinner::PathThinner(double spacing_mm, std::size_t max_points)
    : spacing_(spacing_mm), max_points_(std::max<std::size_t>(max_points, 16)) {}

void PathThinner::add(double t, const Eigen::Vector3d& position, double colour, int line,
                      bool pen_down) {
  colour_since_kept_ = std::max(colour_since_kept_, colour);
  const bool new_line = line != line_ || pen_down != pen_down_;
  line_ = line;
  pen_down_ = pen_down;
  if (points_.empty() || new_line || (position - points_.back().position).norm() >= spacing_) {
    points_.push_back({t, position, colour_since_kept_, pen_down});
    colour_since_kept_ = 0.0;
    has_pending_ = false;
    if (points_.size() > max_points_) rethin();
    return;
  }
  pending_ = {t, position, colour_since_kept_, pen_down};
  has_pending_ = true;
}

void PathThinner::finish() {
  if (has_pending_) points_.push_back(pending_);
  has_pending_ = false;
}

// Twice the spacing, the dropped points' colours carried by the next kept point; a point where
// the pen changes stays, so that pen-up travel is never merged into drawing.
void PathThinner::rethin() {
  spacing_ *= 2.0;
  std::vector<PathPoint> kept{points_.front()};
  double colour = 0.0;
  for (std::size_t i = 1; i < points_.size(); ++i) {
    colour = std::max(colour, points_[i].colour);
    const bool pen_changes =
        i + 1 < points_.size() && points_[i + 1].pen_down != points_[i].pen_down;
    if ((points_[i].position - kept.back().position).norm() >= spacing_ || pen_changes ||
        points_[i].pen_down != kept.back().pen_down || i + 1 == points_.size()) {
      kept.push_back(points_[i]);
      kept.back().colour = colour;
      colour = 0.0;
    }
  }
  points_ = std::move(kept);
}

void MomentSampler::add(double t, const geometry::Pose& pose,
                        const kinematics::JointVector& joints) {
  last_ = {t, pose, joints};
  last_kept_ = seen_ % every_ == 0;
  if (last_kept_) {
    moments_.push_back(last_);
    if (moments_.size() >= 2 * target_) {
      std::vector<Moment> kept;
      for (std::size_t i = 0; i < moments_.size(); i += 2) kept.push_back(moments_[i]);
      moments_ = std::move(kept);
      every_ *= 2;
      last_kept_ = false;  // an even count: the newest moment was the one dropped
    }
  }
  ++seen_;
}

void MomentSampler::finish() {
  if (!last_kept_) moments_.push_back(last_);
  last_kept_ = true;
}

}  // namespace pkm::view

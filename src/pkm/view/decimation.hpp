// Streaming reductions of a long series (a million samples) to what a page can draw in a few
// milliseconds, without losing what a reader looks for: min/max buckets keep every peak and every
// limit crossing of a chart; path thinning keeps the tool path within a spacing of its samples;
// the frame sampler keeps a few hundred evenly spaced moments. Memory does not grow with the
// series: each halves its resolution when it fills.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <span>
#include <vector>

#include "pkm/kinematics/kinematics.hpp"

namespace pkm::view {

// Consecutive samples gathered into buckets holding each channel's min and max (NaN values are
// skipped; a bucket with none holds NaN). When the buckets reach twice `target`, neighbours merge
// and each bucket takes twice as many samples: between `target` and 2 * `target` buckets remain.
class MinMaxBuckets {
 public:
  MinMaxBuckets(int channels, std::size_t target);
  void add(double x, std::span<const double> values);  // x non-decreasing

  std::size_t size() const { return x_first_.size(); }
  int channels() const { return channels_; }
  const std::vector<double>& x_first() const { return x_first_; }
  const std::vector<double>& x_last() const { return x_last_; }
  const std::vector<double>& min(int channel) const { return min_[channel]; }
  const std::vector<double>& max(int channel) const { return max_[channel]; }
  std::size_t samples_per_bucket() const { return per_bucket_; }

 private:
  void halve();
  int channels_;
  std::size_t target_;
  std::size_t per_bucket_ = 1;
  std::size_t in_last_ = 0;  // samples in the last bucket
  std::vector<double> x_first_, x_last_;
  std::vector<std::vector<double>> min_, max_;
};

// One kept point of a thinned path: where, when (the slider's parameter) and the largest colour
// value (speed, deviation) of the samples it stands for, and whether a plotter's pen was down on
// the way to it (true on machines without a pen).
struct PathPoint {
  double t = 0.0;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double colour = 0.0;
  bool pen_down = true;
};

// Keeps a sample when it lies at least `spacing` from the last kept one, or starts a new G-code
// line or lifts or lowers the pen (so corners, move ends and pen changes stay); past `max_points`,
// the spacing doubles and the kept points are thinned again. The last sample is always kept
// (finish()).
class PathThinner {
 public:
  PathThinner(double spacing_mm, std::size_t max_points);
  void add(double t, const Eigen::Vector3d& position, double colour, int line,
           bool pen_down = true);
  void finish();
  const std::vector<PathPoint>& points() const { return points_; }
  double spacing_mm() const { return spacing_; }

 private:
  void rethin();
  double spacing_;
  std::size_t max_points_;
  std::vector<PathPoint> points_;
  PathPoint pending_;  // the last sample not kept, with the colour since the last kept one
  bool has_pending_ = false;
  double colour_since_kept_ = 0.0;
  int line_ = -1;
  bool pen_down_ = true;
};

// A moment at which the machine is drawn.
struct Moment {
  double t = 0.0;
  geometry::Pose pose;
  kinematics::JointVector joints;
};

// Every k-th sample, k doubling whenever 2 * `target` moments are held: between `target` and
// 2 * `target` evenly spaced moments, the first sample's among them; finish() adds the last.
class MomentSampler {
 public:
  explicit MomentSampler(std::size_t target) : target_(target) {}
  void add(double t, const geometry::Pose& pose, const kinematics::JointVector& joints);
  void finish();
  const std::vector<Moment>& moments() const { return moments_; }

 private:
  std::size_t target_;
  std::size_t every_ = 1, seen_ = 0;
  std::vector<Moment> moments_;
  Moment last_;
  bool last_kept_ = true;
};

}  // namespace pkm::view

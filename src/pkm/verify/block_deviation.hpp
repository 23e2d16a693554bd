// The deviation of one joint-linear block from the stretch of the job it must trace: the tool
// path reconstructed by forward kinematics, sampled adaptively until the largest distance found is
// within 0.4 % of an upper estimate of the true largest (docs/post.md, "pkm verify").
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "pkm/machine/machine.hpp"
#include "pkm/verify/job_cursor.hpp"

namespace pkm::verify {

struct BlockDeviation {
  double max_mm = 0.0;
  int job_line = 0;                 // the move of the stretch nearest where the block peaks
  double sum_of_squares_mm2 = 0.0;  // over the uniform grid of the block, for the RMS
  int grid_points = 0;
  int halvings = 0;  // intervals halved beyond the grid to find the peak: the work it took
};

class BlockMeasure {
 public:
  static constexpr int kGrid = 16;  // intervals of the uniform grid
  explicit BlockMeasure(const machine::Machine& machine);

  // Forward kinematics on a uniform grid along the block from q0 to q1 (FK seeded with `seed`, the
  // pose at q0). False where forward kinematics fails.
  bool sample_grid(const kinematics::JointVector& q0, const kinematics::JointVector& q1,
                   const geometry::Pose& seed);
  double grid_length_mm() const;  // the tool path's length as the grid sees it
  // The box of the grid's points (controlled coordinates), each side moved out by `margin_mm`.
  Eigen::AlignedBox3d grid_box(double margin_mm) const;
  const Eigen::Vector3d& end_point() const { return samples_[kGrid].point; }
  const geometry::Pose& end_pose() const { return samples_[kGrid].pose; }
  // The grid's poses, k = 0..kGrid, after sample_grid (before measure refines between them).
  const geometry::Pose& grid_pose(int k) const {
    return samples_[static_cast<std::size_t>(k)].pose;
  }

  // The largest distance of the block from `stretch`, refined where the samples leave room for a
  // larger one; where refinement stops short (a budget per block, or a block already a hundred
  // tolerances off), the upper estimate of what is left. False where forward kinematics fails.
  bool measure(const std::vector<PieceRange>& stretch, double tolerance_mm, BlockDeviation& result);

 private:
  struct Sample {
    double lambda = 0.0;
    geometry::Pose pose;
    Eigen::Vector3d point = Eigen::Vector3d::Zero();  // controlled coordinates
    double distance_mm = 0.0;
    int nearest_range = 0;
  };
  struct Interval {
    std::size_t a, middle, b;
    int depth;
  };

  bool add_sample(double lambda, const geometry::Pose& seed);
  void measure_sample(std::size_t index);
  double upper_estimate(const Interval& interval) const;

  const machine::Machine& machine_;
  Eigen::Vector3d mask_;
  kinematics::JointVector q0_, q1_;
  const std::vector<PieceRange>* stretch_ = nullptr;
  std::vector<Sample> samples_;
  std::vector<double> distances_;  // per sample, per range of the stretch
  std::vector<Interval> pending_;
};

}  // namespace pkm::verify

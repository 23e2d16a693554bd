#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::test {

// Distance from p to the line segment from a to b (mm): how far a sample lies from a move.
inline double distance_to_segment(const Eigen::Vector3d& p, const Eigen::Vector3d& a,
                                  const Eigen::Vector3d& b) {
  const Eigen::Vector3d ab = b - a;
  const double squared = ab.squaredNorm();
  const double u = squared > 0.0 ? std::clamp((p - a).dot(ab) / squared, 0.0, 1.0) : 0.0;
  return (a + u * ab - p).norm();
}

// Distance from p to the polyline through `points` (mm); infinity for fewer than two points.
inline double distance_to_polyline(const Eigen::Vector3d& p,
                                   const std::vector<Eigen::Vector3d>& points) {
  double nearest = INFINITY;
  for (std::size_t k = 1; k < points.size(); ++k) {
    nearest = std::min(nearest, distance_to_segment(p, points[k - 1], points[k]));
  }
  return nearest;
}

std::filesystem::path example_machine_path(const std::string& file_name);
machine::Machine load_example(const std::string& file_name);
// A Cartesian machine (a unit matrix; joints x y z, mm, travel +-1000 mm, home at the origin,
// max_feed 100 mm/s) whose joints carry the limits given as TOML keys (max_velocity = ...,
// max_acceleration = ...), and its tool's max_acceleration (mm/s^2).
inline constexpr const char* kFastCartesianJoint =
    "max_velocity = 1000.0\nmax_acceleration = 100000.0\n";
machine::Machine cartesian_machine(const std::string& x_keys, const std::string& y_keys,
                                   const std::string& z_keys = kFastCartesianJoint,
                                   double tool_acceleration_mm_per_s2 = 1000.0);

// An example machine with every `from` in its file's text replaced by `to`.
machine::Machine load_example_changed(const std::string& file_name, const std::string& from,
                                      const std::string& to);
// File names of every machine in examples/machines, sorted.
std::vector<std::string> example_machine_files();
// A file name as a GoogleTest parameter name: its stem, non-alphanumerics as '_'.
std::string test_name(const std::string& file_name);

// Ratio of smallest to largest singular value of d joints / d pose over the controlled
// coordinates, angles scaled by 100 mm/rad: 0 at a singularity, 1 where every direction of tool
// motion moves the joints alike.
double dexterity(const kinematics::Kinematics& kinematics, const geometry::Pose& pose);

// Uniform random poses in the box spanned by the machine's reachable extent (angles clipped to
// +-max_angle_deg), kept only where the machine's IK and joint limits accept them and the
// dexterity is at least min_dexterity: poses a machine can work at, not its singular fringe.
std::vector<geometry::Pose> sample_reachable_poses(const machine::Machine& machine, int count,
                                                   std::mt19937_64& rng,
                                                   double max_angle_deg = 25.0,
                                                   double min_dexterity = 0.0);

// [[joints]] tables leg1..legN, linear from `min` to `max` mm.
std::string joints_text(int count, double min, double max);
// Joints u and v of a test model in code: travel -1000..1000 mm, 100 mm/s, 1000 mm/s^2.
std::vector<machine::JointSpec> test_model_joints_uv();
// A hexapod's machine file: joints at `base` and `platform` [x, y, 0], `extra_keys` in
// [kinematics], home 500 mm above the base.
std::string hexapod_text(const std::vector<std::array<double, 2>>& base,
                         const std::vector<std::array<double, 2>>& platform,
                         const std::string& extra_keys);
// Platform joints 10 mm off the base joints `points`, each in another direction (leg k towards
// 100 k deg): legs nearly parallel at home, yet a hexapod that can move.
std::vector<std::array<double, 2>> platform_off_base(std::vector<std::array<double, 2>> points);
// The hexapod with its platform joints straight above its base joints `points`, its legs
// parallel at home. Parallel legs make a hexapod singular everywhere and such a file is refused
// (docs/bad-input.md); but leg limits are the model's, per pose, and parallel legs make them
// computable by hand. So the file gives platform_off_base, which loads, and the model then
// takes the platform straight above the base.
machine::Machine parallel_leg_hexapod(const std::vector<std::array<double, 2>>& points,
                                      const std::string& extra_keys);
// Six joints on a circle of radius 300 mm, at 30, 90, ..., 330 deg.
std::vector<std::array<double, 2>> hexagon_points();
// Legs 1 and 2 60 mm apart along x, the others at least 300 mm apart across x.
std::vector<std::array<double, 2>> close_pair_points();

// A G-code program in a temporary file of its own, removed with the object.
class TempProgram {
 public:
  explicit TempProgram(const std::string& text);
  ~TempProgram();
  TempProgram(const TempProgram&) = delete;
  TempProgram& operator=(const TempProgram&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace pkm::test

#include "test_support.hpp"

#include <unistd.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <fstream>
#include <stdexcept>

namespace pkm::test {

TempProgram::TempProgram(const std::string& text) {
  static int counter = 0;
  path_ = std::filesystem::temp_directory_path() /
          ("pkm-test-" + std::to_string(::getpid()) + "-" + std::to_string(counter++) + ".ngc");
  std::ofstream(path_) << text;
}

TempProgram::~TempProgram() {
  std::error_code ignored;
  std::filesystem::remove(path_, ignored);
}

std::filesystem::path example_machine_path(const std::string& file_name) {
  return std::filesystem::path(PKM_SOURCE_DIR) / "examples" / "machines" / file_name;
}

Machine load_example(const std::string& file_name) {
  return load_machine(example_machine_path(file_name));
}

std::vector<std::string> example_machine_files() {
  std::vector<std::string> files;
  for (const auto& entry :
       std::filesystem::directory_iterator(example_machine_path("").parent_path())) {
    if (entry.path().extension() == ".toml") files.push_back(entry.path().filename().string());
  }
  std::sort(files.begin(), files.end());
  return files;
}

double dexterity(const Kinematics& kinematics, const Pose& pose) {
  JointJacobian jacobian;
  if (!kinematics.jacobian(pose, jacobian).ok()) return 0.0;
  Eigen::MatrixXd reduced(jacobian.rows(), kinematics.dof().count());
  for (int axis = 0, k = 0; axis < kPoseSize; ++axis) {
    if (!kinematics.dof().controls(axis)) continue;
    reduced.col(k++) = jacobian.col(axis) * (axis < 3 ? 1.0 : 1.0 / 100.0);
  }
  // Rotary joints (a matrix machine's pass-through axes) read rad: on the same 100 mm/rad scale.
  for (int joint = 0; joint < kinematics.joint_count(); ++joint) {
    if (kinematics.joint_kind(joint) == JointKind::rotary) reduced.row(joint) *= 100.0;
  }
  const Eigen::VectorXd singular_values = reduced.jacobiSvd().singularValues();
  return singular_values.minCoeff() / singular_values.maxCoeff();
}

std::string test_name(const std::string& file_name) {
  std::string name = file_name.substr(0, file_name.find('.'));
  for (char& c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  }
  return name;
}

std::vector<Pose> sample_reachable_poses(const Machine& machine, int count, std::mt19937_64& rng,
                                         double max_angle_deg, double min_dexterity) {
  const std::vector<AxisExtent> extents = reachable_extent(machine);
  std::vector<Pose> poses;
  JointVector joints;
  const long max_attempts = 1000L * count;
  for (long attempt = 0; attempt < max_attempts && static_cast<int>(poses.size()) < count;
       ++attempt) {
    Vector6d values = machine.home().as_vector();
    for (const AxisExtent& extent : extents) {
      double low = extent.min;
      double high = extent.max;
      if (extent.axis >= 3) {
        low = std::max(low, degrees_to_radians(-max_angle_deg));
        high = std::min(high, degrees_to_radians(max_angle_deg));
      }
      values[extent.axis] = std::uniform_real_distribution<double>(low, high)(rng);
    }
    const Pose pose = Pose::from_vector(values);
    if (!machine.inverse(pose, joints).ok()) continue;
    if (min_dexterity > 0.0 && dexterity(machine.kinematics(), pose) < min_dexterity) continue;
    poses.push_back(pose);
  }
  if (static_cast<int>(poses.size()) < count) {
    throw std::runtime_error("could not sample enough reachable poses for " + machine.name());
  }
  return poses;
}

}  // namespace pkm::test

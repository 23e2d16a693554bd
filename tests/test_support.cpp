#include "test_support.hpp"

#include <unistd.h>

#include <Eigen/SVD>
#include <algorithm>
#include <cctype>
#include <cmath>
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

machine::Machine load_example(const std::string& file_name) {
  return machine::load_machine(example_machine_path(file_name));
}

machine::Machine cartesian_machine(const std::string& x_keys, const std::string& y_keys,
                                   const std::string& z_keys, double tool_acceleration_mm_per_s2) {
  std::string text =
      "name = \"Cartesian test mill\"\nunits = \"mm\"\n[kinematics]\n"
      "type = \"matrix\"\n"
      "matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]\n";
  const char* names[3] = {"x", "y", "z"};
  const std::string* keys[3] = {&x_keys, &y_keys, &z_keys};
  for (int i = 0; i < 3; ++i) {
    text += std::string("[[joints]]\nname = \"") + names[i] +
            "\"\nmin = -1000.0\nmax = 1000.0\naxis = \"" + static_cast<char>('X' + i) + "\"\n" +
            *keys[i];
  }
  text += "[cartesian]\nmax_feed = 6000.0\nmax_acceleration = " +
          std::to_string(tool_acceleration_mm_per_s2) + "\nhome = [0.0, 0.0, 0.0]\n";
  return machine::parse_machine(text, "cartesian-test.toml");
}

machine::Machine load_example_changed(const std::string& file_name, const std::string& from,
                                      const std::string& to) {
  std::ifstream in(example_machine_path(file_name));
  std::string text((std::istreambuf_iterator<char>(in)), {});
  for (std::size_t at = text.find(from); at != std::string::npos; at = text.find(from, at)) {
    text.replace(at, from.size(), to);
    at += to.size();
  }
  return machine::parse_machine(text, file_name);
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

double dexterity(const kinematics::Kinematics& kinematics, const geometry::Pose& pose) {
  kinematics::JointJacobian jacobian;
  if (!kinematics.jacobian(pose, jacobian).ok()) return 0.0;
  Eigen::MatrixXd reduced(jacobian.rows(), kinematics.dof().count());
  for (int axis = 0, k = 0; axis < geometry::kPoseSize; ++axis) {
    if (!kinematics.dof().controls(axis)) continue;
    reduced.col(k++) = jacobian.col(axis) * (axis < 3 ? 1.0 : 1.0 / 100.0);
  }
  // Rotary joints (a matrix machine's pass-through axes) read rad: on the same 100 mm/rad scale.
  for (int joint = 0; joint < kinematics.joint_count(); ++joint) {
    if (kinematics.joint_kind(joint) == kinematics::JointKind::rotary) reduced.row(joint) *= 100.0;
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

std::vector<geometry::Pose> sample_reachable_poses(const machine::Machine& machine, int count,
                                                   std::mt19937_64& rng, double max_angle_deg,
                                                   double min_dexterity) {
  const std::vector<machine::AxisExtent> extents = machine::reachable_extent(machine);
  std::vector<geometry::Pose> poses;
  kinematics::JointVector joints;
  const long max_attempts = 1000L * count;
  for (long attempt = 0; attempt < max_attempts && static_cast<int>(poses.size()) < count;
       ++attempt) {
    geometry::Vector6d values = machine.home().as_vector();
    for (const machine::AxisExtent& extent : extents) {
      double low = extent.min;
      double high = extent.max;
      if (extent.axis >= 3) {
        low = std::max(low, geometry::degrees_to_radians(-max_angle_deg));
        high = std::min(high, geometry::degrees_to_radians(max_angle_deg));
      }
      values[extent.axis] = std::uniform_real_distribution<double>(low, high)(rng);
    }
    const geometry::Pose pose = geometry::Pose::from_vector(values);
    if (!machine.inverse(pose, joints).ok()) continue;
    if (min_dexterity > 0.0 && dexterity(machine.kinematics(), pose) < min_dexterity) continue;
    poses.push_back(pose);
  }
  if (static_cast<int>(poses.size()) < count) {
    throw std::runtime_error("could not sample enough reachable poses for " + machine.name());
  }
  return poses;
}

std::vector<machine::JointSpec> test_model_joints_uv() {
  std::vector<machine::JointSpec> joints(2);
  joints[0].name = "u";
  joints[1].name = "v";
  for (machine::JointSpec& joint : joints) {
    joint.min = -1000.0;
    joint.max = 1000.0;
    joint.max_velocity = 100.0;
    joint.max_acceleration = 1000.0;
  }
  return joints;
}

std::string joints_text(int count, double min, double max) {
  std::string text;
  for (int i = 1; i <= count; ++i) {
    text += "[[joints]]\nname = \"leg" + std::to_string(i) + "\"\nmin = " + std::to_string(min) +
            "\nmax = " + std::to_string(max) + "\nmax_velocity = 100\nmax_acceleration = 1000\n";
  }
  return text;
}

namespace {
std::string points_text(const std::vector<std::array<double, 2>>& points) {
  std::string text;
  for (const auto& [x, y] : points) {
    text += (text.empty() ? "[" : ", [") + std::to_string(x) + ", " + std::to_string(y) + ", 0]";
  }
  return text;
}
}  // namespace

std::string hexapod_text(const std::vector<std::array<double, 2>>& base,
                         const std::vector<std::array<double, 2>>& platform,
                         const std::string& extra_keys) {
  return "name = \"parallel legs\"\n[kinematics]\ntype = \"hexapod\"\nbase = [" +
         points_text(base) + "]\nplatform = [" + points_text(platform) + "]\ntool_length = 0\n" +
         extra_keys + "\n" + joints_text(6, 100, 2000) +
         "[cartesian]\nmax_feed = 6000\nmax_acceleration = 1000\nhome = [0, 0, 500, 0, 0, 0]\n";
}

std::vector<std::array<double, 2>> platform_off_base(std::vector<std::array<double, 2>> points) {
  for (std::size_t leg = 0; leg < points.size(); ++leg) {
    const double towards = geometry::degrees_to_radians(100.0 * static_cast<double>(leg));
    points[leg][0] += 10.0 * std::cos(towards);
    points[leg][1] += 10.0 * std::sin(towards);
  }
  return points;
}

machine::Machine parallel_leg_hexapod(const std::vector<std::array<double, 2>>& points,
                                      const std::string& extra_keys) {
  machine::Machine machine = machine::parse_machine(
      hexapod_text(points, platform_off_base(points), extra_keys), "parallel.toml");
  std::vector<double> values;
  for (const kinematics::Parameter& parameter : machine.kinematics().parameters()) {
    values.push_back(parameter.value);
  }
  constexpr int kPerLeg = 7;  // base x y z, platform x y z, offset
  for (int leg = 0; leg < 6; ++leg) {
    for (int k = 0; k < 3; ++k) values[kPerLeg * leg + 3 + k] = values[kPerLeg * leg + k];
  }
  machine.kinematics().set_parameters(values);
  machine.kinematics().set_home(machine.home());  // the joints' neutral axes, from the new legs
  return machine;
}

std::vector<std::array<double, 2>> hexagon_points() {
  std::vector<std::array<double, 2>> points;
  for (int k = 0; k < 6; ++k) {
    const double phi = geometry::degrees_to_radians(30.0 + 60.0 * k);
    points.push_back({300.0 * std::cos(phi), 300.0 * std::sin(phi)});
  }
  return points;
}
std::vector<std::array<double, 2>> close_pair_points() {
  return {{-30, 200}, {30, 200}, {300, -150}, {-300, -150}, {150, -500}, {-150, -520}};
}

}  // namespace pkm::test

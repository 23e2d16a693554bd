// What a kinematic model writes to its section of a machine file: the mirror of ModelConfig. Each
// model writes its own keys (Kinematics::write_config) beside the function that reads them; the
// machine module turns the calls into TOML (machine_writer.hpp), lengths in the file's unit.
#pragma once

#include <Eigen/Core>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "pkm/geometry/pose.hpp"

namespace pkm::kinematics {

class ModelConfigWriter {
 public:
  virtual ~ModelConfigWriter() = default;

  // Dimensionless numbers.
  virtual void number(std::string_view key, double value) = 0;
  virtual void whole_number(std::string_view key, long long value) = 0;
  virtual void number_list(std::string_view key, std::span<const double> values) = 0;
  // Lengths in mm, written in the file's unit.
  virtual void length(std::string_view key, double mm) = 0;
  virtual void length_list(std::string_view key, std::span<const double> mm) = 0;
  // An array of points, each a list of lengths (mm).
  virtual void length_points(std::string_view key,
                             const std::vector<std::vector<double>>& points_mm) = 0;
  // An array of 3 rows of 3 numbers.
  virtual void matrix3(std::string_view key, const Eigen::Matrix3d& rows) = 0;
  virtual void boolean(std::string_view key, bool value) = 0;
  virtual void string(std::string_view key, std::string_view value) = 0;
  virtual void string_list(std::string_view key, std::span<const std::string> values) = 0;
  // Sub-tables of numbers or strings, in the order given.
  virtual void number_table(std::string_view key,
                            const std::vector<std::pair<std::string, double>>& entries) = 0;
  virtual void string_table(std::string_view key,
                            const std::vector<std::pair<std::string, std::string>>& entries) = 0;
  // A new table at the end of the array of tables `key` ([[kinematics.rails]]), to write its keys
  // to; valid until the next call on this writer.
  virtual ModelConfigWriter& table_list_entry(std::string_view key) = 0;

  // Conveniences over the required calls, the mirrors of ModelConfig's.
  void vector3(std::string_view key, const Eigen::Vector3d& v) {
    number_list(key, std::span<const double>(v.data(), 3));
  }
  void length_vector3(std::string_view key, const Eigen::Vector3d& mm) {
    length_list(key, std::span<const double>(mm.data(), 3));
  }
  // The names of the axes `dof` controls, in pose order (`axes = ["x", "y"]`).
  void axis_list(std::string_view key, geometry::Dof dof) {
    std::vector<std::string> names;
    for (int axis = 0; axis < geometry::kPoseSize; ++axis) {
      if (dof.controls(axis)) names.emplace_back(geometry::kAxisNames[axis]);
    }
    string_list(key, names);
  }
  void length_vector3_list(std::string_view key, std::span<const Eigen::Vector3d> points_mm) {
    std::vector<std::vector<double>> points;
    for (const Eigen::Vector3d& p : points_mm) points.push_back({p.x(), p.y(), p.z()});
    length_points(key, points);
  }
  void length_vector2_list(std::string_view key, std::span<const Eigen::Vector2d> points_mm) {
    std::vector<std::vector<double>> points;
    for (const Eigen::Vector2d& p : points_mm) points.push_back({p.x(), p.y()});
    length_points(key, points);
  }
};

}  // namespace pkm::kinematics

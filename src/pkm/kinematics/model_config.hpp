// What a kinematic model reads from its section of a machine file. The machine module implements
// it over TOML (with file:line:key errors and unit conversion); each model reads its own keys, so a
// model's keys live beside its equations.
#pragma once

#include <Eigen/Core>
#include <memory>
#include <stdexcept>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace pkm::kinematics {

class ModelConfig {
 public:
  virtual ~ModelConfig() = default;

  virtual bool has(std::string_view key) const = 0;
  // Dimensionless numbers.
  virtual double number(std::string_view key) const = 0;
  virtual std::vector<double> number_list(std::string_view key) const = 0;
  // Lengths, converted from the file's units to mm.
  virtual double length(std::string_view key) const = 0;
  virtual std::vector<double> length_list(std::string_view key) const = 0;
  virtual Eigen::Vector3d length_vector3(std::string_view key) const = 0;
  // An array of points, each `dimension` lengths ([[x, y], ...] or [[x, y, z], ...]).
  virtual std::vector<std::vector<double>> length_points(std::string_view key,
                                                         std::size_t dimension) const = 0;
  // An array of 3 rows of 3 numbers.
  virtual Eigen::Matrix3d matrix3(std::string_view key) const = 0;
  virtual bool boolean(std::string_view key) const = 0;
  // Whether the value at `key` is an array (keys that take a number or a list).
  virtual bool is_list(std::string_view key) const = 0;
  virtual std::string string(std::string_view key) const = 0;
  virtual std::vector<std::string> string_list(std::string_view key) const = 0;
  // Sub-tables of numbers or strings, in file order.
  virtual std::vector<std::pair<std::string, double>> number_table(std::string_view key) const = 0;
  virtual std::vector<std::pair<std::string, std::string>> string_table(
      std::string_view key) const = 0;
  // An array of tables ([[kinematics.rails]]).
  virtual std::vector<std::unique_ptr<ModelConfig>> table_list(std::string_view key) const = 0;

  // Names of the machine's joints, in file order (models that key values by joint name).
  virtual std::vector<std::string> joint_names() const = 0;

  // mm per unit of length in the file (1 for mm, 25.4 for inch).
  virtual double mm_per_file_unit() const = 0;

  // Throws an error that names the file, the line and the key.
  [[noreturn]] void fail(std::string_view key, std::string_view message) const {
    raise(key, message);
    throw std::logic_error("ModelConfig::raise returned");
  }

  // The implementation of fail(): must throw.
  virtual void raise(std::string_view key, std::string_view message) const = 0;

  // Conveniences over the required accessors.
  double length_or(std::string_view key, double fallback_mm) const {
    return has(key) ? length(key) : fallback_mm;
  }
  double number_or(std::string_view key, double fallback) const {
    return has(key) ? number(key) : fallback;
  }
  bool boolean_or(std::string_view key, bool fallback) const {
    return has(key) ? boolean(key) : fallback;
  }
  std::vector<Eigen::Vector3d> length_vector3_list(std::string_view key) const {
    std::vector<Eigen::Vector3d> points;
    for (const std::vector<double>& p : length_points(key, 3))
      points.emplace_back(p[0], p[1], p[2]);
    return points;
  }
  std::vector<Eigen::Vector2d> length_vector2_list(std::string_view key) const {
    std::vector<Eigen::Vector2d> points;
    for (const std::vector<double>& p : length_points(key, 2)) points.emplace_back(p[0], p[1]);
    return points;
  }
};

}  // namespace pkm::kinematics

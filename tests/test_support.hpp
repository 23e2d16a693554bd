#pragma once

#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "pkm/machine/machine.hpp"

namespace pkm::test {

std::filesystem::path example_machine_path(const std::string& file_name);
Machine load_example(const std::string& file_name);
// File names of every machine in examples/machines, sorted.
std::vector<std::string> example_machine_files();
// A file name as a GoogleTest parameter name: its stem, non-alphanumerics as '_'.
std::string test_name(const std::string& file_name);

// Ratio of smallest to largest singular value of d joints / d pose over the controlled
// coordinates, angles scaled by 100 mm/rad: 0 at a singularity, 1 where every direction of tool
// motion moves the joints alike.
double dexterity(const Kinematics& kinematics, const Pose& pose);

// Uniform random poses in the box spanned by the machine's reachable extent (angles clipped to
// +-max_angle_deg), kept only where the machine's IK and joint limits accept them and the
// dexterity is at least min_dexterity: poses a machine can work at, not its singular fringe.
std::vector<Pose> sample_reachable_poses(const Machine& machine, int count, std::mt19937_64& rng,
                                         double max_angle_deg = 25.0, double min_dexterity = 0.0);

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

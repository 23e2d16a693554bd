// For tools/compare-outputs: every machine file given, its [kinematics] section as the machine
// writer writes it back (pkm calibrate's -o path), in mm and in inch, and the whole file with
// that section replaced. Built by the script against a build's libraries, so that the writer's
// output before and after a change can be compared byte for byte.
#include <cstdio>
#include <exception>
#include <fstream>
#include <sstream>

#include "pkm/machine/machine.hpp"
#include "pkm/machine/machine_writer.hpp"

int main(int argc, char** argv) {
  int failures = 0;
  for (int i = 1; i < argc; ++i) {
    std::printf("==> %s\n", argv[i]);
    try {
      const pkm::machine::Machine machine = pkm::machine::load_machine(argv[i]);
      std::printf("--- mm\n%s",
                  pkm::machine::kinematics_toml(machine.kinematics(), pkm::machine::LengthUnit::mm)
                      .c_str());
      std::printf("--- inch\n%s", pkm::machine::kinematics_toml(machine.kinematics(),
                                                                pkm::machine::LengthUnit::inch)
                                      .c_str());
      std::ifstream in(argv[i]);
      std::stringstream text;
      text << in.rdbuf();
      std::printf("--- replaced\n%s",
                  pkm::machine::replace_kinematics_section(text.str(), argv[i],
                                                           machine.kinematics(), machine.units())
                      .c_str());
    } catch (const std::exception& error) {
      std::printf("error: %s\n", error.what());
      ++failures;
    }
  }
  return failures == 0 ? 0 : 1;
}

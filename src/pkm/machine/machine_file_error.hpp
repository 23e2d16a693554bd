#pragma once

#include <stdexcept>
#include <string>

namespace pkm::machine {

// An error in a machine file, located as file:line:key; or a file that cannot be read at all
// ("file: cannot open (reason)", line 0).
class MachineFileError : public std::runtime_error {
 public:
  MachineFileError(std::string file, const std::string& message)
      : std::runtime_error(file + ": " + message), file_(std::move(file)), line_(0) {}
  MachineFileError(std::string file, int line, std::string key, const std::string& message)
      : std::runtime_error(file + ":" + std::to_string(line) + ":" + key + ": " + message),
        file_(std::move(file)),
        line_(line),
        key_(std::move(key)) {}
  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& key() const { return key_; }

 private:
  std::string file_;
  int line_;
  std::string key_;
};

}  // namespace pkm::machine

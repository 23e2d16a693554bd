// Where a sender's bytes go: a serial port opened raw at a baud rate (termios), or grbl-sim
// started on a pseudo-terminal, its step positions recorded on request. Both are file
// descriptors the sender reads and writes without blocking; they close (and the simulator is
// stopped) when the object goes.
#pragma once

#include <sys/types.h>

#include <filesystem>
#include <string>

namespace pkm::stream {

class Port {
 public:
  Port() = default;
  Port(const Port&) = delete;
  Port& operator=(const Port&) = delete;
  Port(Port&& other) noexcept;
  Port& operator=(Port&& other) noexcept;
  ~Port();

  int fd() const { return fd_; }
  const std::string& name() const { return name_; }

  // Opens DEVICE raw (8N1, no flow control) at `baud` bit/s. Throws StreamError naming the
  // device and the reason (missing, not a terminal, a baud the system cannot set).
  static Port open_serial(const std::string& device, int baud);

  struct SimulatorOptions {
    std::filesystem::path executable;  // grbl_sim.exe (build-sim, cmake/GrblSim.cmake)
    std::filesystem::path step_file;   // -s: step positions (empty: none)
    double step_interval_s = 0.01;     // -r: how often they are written, simulated seconds
    // -t: simulated seconds per second. grbl-sim simulates each tick of a 16 MHz AVR; where the
    // computer cannot keep up, it falls further and further behind (it catches up in ever longer
    // stretches, during which it neither quits nor flushes), so it is run slower than real time.
    double clock_factor = 0.5;
  };
  // Starts grbl-sim on a pty set raw (one byte at a time, no echo), as a UART would deliver, in
  // a directory of its own.
  static Port start_simulator(const SimulatorOptions& options);

 private:
  void close_and_reap() noexcept;
  int fd_ = -1;
  pid_t child_ = -1;  // the simulator's process, or -1
  // The simulator's working directory: grbl-sim keeps its EEPROM there (EEPROM.DAT), so each run
  // starts from grbl's defaults and leaves nothing in the user's directory.
  std::filesystem::path scratch_;
  std::string name_;
};

}  // namespace pkm::stream

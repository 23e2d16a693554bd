#include "pkm/stream/port.hpp"

#include <fcntl.h>
#include <pty.h>
#include <signal.h>
#include <sys/wait.h>
#include <termios.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <thread>
#include <utility>
#include <vector>

#include "pkm/stream/grbl_sender.hpp"

namespace pkm::stream {

namespace {

speed_t speed_of(int baud) {
  switch (baud) {
    case 9600:
      return B9600;
    case 19200:
      return B19200;
    case 38400:
      return B38400;
    case 57600:
      return B57600;
    case 115200:
      return B115200;
    case 230400:
      return B230400;
    case 460800:
      return B460800;
    case 500000:
      return B500000;
    case 921600:
      return B921600;
    case 1000000:
      return B1000000;
    case 2000000:
      return B2000000;
    default:
      return B0;
  }
}

std::string system_error() {
  return std::strerror(errno);
}

}  // namespace

Port::Port(Port&& other) noexcept
    : fd_(std::exchange(other.fd_, -1)),
      child_(std::exchange(other.child_, -1)),
      scratch_(std::exchange(other.scratch_, {})),
      name_(std::move(other.name_)) {}

Port& Port::operator=(Port&& other) noexcept {
  if (this != &other) {
    close_and_reap();
    fd_ = std::exchange(other.fd_, -1);
    child_ = std::exchange(other.child_, -1);
    scratch_ = std::exchange(other.scratch_, {});
    name_ = std::move(other.name_);
  }
  return *this;
}

Port::~Port() {
  close_and_reap();
}

void Port::close_and_reap() noexcept {
  if (fd_ >= 0 && child_ > 0) {
    // grbl-sim ends at ^F once idle; the files it writes are then flushed.
    const char end = 0x06;
    (void)::write(fd_, &end, 1);
  }
  if (child_ > 0) {
    // It quits once idle after ^F; a reset grbl is idle at once. Give it two seconds.
    for (int i = 0; i < 200; ++i) {
      if (::waitpid(child_, nullptr, WNOHANG) == child_) {
        child_ = -1;
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(10));
    }
    if (child_ > 0) {
      ::kill(child_, SIGKILL);
      ::waitpid(child_, nullptr, 0);
      child_ = -1;
    }
  }
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
  if (!scratch_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(scratch_, ignored);
    scratch_.clear();
  }
}

Port Port::open_serial(const std::string& device, int baud) {
  const speed_t speed = speed_of(baud);
  if (speed == B0) {
    throw StreamError(device + ": --baud " + std::to_string(baud) +
                      " is not a rate a serial port takes (9600, 19200, 38400, 57600, 115200, "
                      "230400, ... 2000000)");
  }
  Port port;
  port.name_ = device;
  port.fd_ = ::open(device.c_str(), O_RDWR | O_NOCTTY | O_NONBLOCK | O_CLOEXEC);
  if (port.fd_ < 0) throw StreamError(device + ": cannot open (" + system_error() + ")");
  termios settings{};
  if (::tcgetattr(port.fd_, &settings) != 0) {
    throw StreamError(device + ": not a serial port (" + system_error() + ")");
  }
  ::cfmakeraw(&settings);
  settings.c_cflag |= CLOCAL | CREAD;
  settings.c_cflag &= ~static_cast<tcflag_t>(CSTOPB | CRTSCTS);
  if (::cfsetispeed(&settings, speed) != 0 || ::cfsetospeed(&settings, speed) != 0 ||
      ::tcsetattr(port.fd_, TCSANOW, &settings) != 0) {
    throw StreamError(device + ": cannot set " + std::to_string(baud) + " baud (" + system_error() +
                      ")");
  }
  ::tcflush(port.fd_, TCIOFLUSH);
  return port;
}

Port Port::start_simulator(const SimulatorOptions& options) {
  if (::access(options.executable.c_str(), X_OK) != 0) {
    throw StreamError(options.executable.string() + ": cannot run grbl-sim (" + system_error() +
                      "); build it with ../shared/controllers/grbl-1.1h/build-sim DEST, or the "
                      "build's grbl_sim target, and give --grbl-sim PATH");
  }
  Port port;
  port.name_ = "grbl-sim";
  std::string scratch = (std::filesystem::temp_directory_path() / "pkm-grbl-sim-XXXXXX").string();
  if (::mkdtemp(scratch.data()) == nullptr) {
    throw StreamError(scratch + ": cannot make grbl-sim's directory (" + system_error() + ")");
  }
  port.scratch_ = scratch;
  // The arguments are made before the fork: the child only changes directory and calls exec.
  std::vector<std::string> arguments = {std::filesystem::absolute(options.executable).string(),
                                        "-n",
                                        "-b",
                                        "/dev/null",
                                        "-t",
                                        std::to_string(options.clock_factor)};
  if (!options.step_file.empty()) {
    arguments.insert(arguments.end(), {"-s", std::filesystem::absolute(options.step_file).string(),
                                       "-r", std::to_string(options.step_interval_s)});
  }
  std::vector<char*> argv;
  for (std::string& argument : arguments) argv.push_back(argument.data());
  argv.push_back(nullptr);
  termios raw{};
  ::cfmakeraw(&raw);
  const pid_t child = ::forkpty(&port.fd_, nullptr, &raw, nullptr);
  if (child < 0) throw StreamError("grbl-sim: cannot start it on a pty (" + system_error() + ")");
  if (child == 0) {
    if (::chdir(scratch.c_str()) != 0) ::_exit(126);
    ::execv(argv[0], argv.data());
    ::_exit(127);
  }
  port.child_ = child;
  ::fcntl(port.fd_, F_SETFL, ::fcntl(port.fd_, F_GETFL) | O_NONBLOCK);
  ::fcntl(port.fd_, F_SETFD, FD_CLOEXEC);
  return port;
}

}  // namespace pkm::stream

#include "pkm/stream/grbl_sender.hpp"

#include <poll.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <utility>

namespace pkm::stream {

namespace {

constexpr std::size_t kLongestReply = 256;  // grbl's longest line is well under this
constexpr std::size_t kShownBytes = 80;     // what came instead of a banner, shown to the user
constexpr double kHoldTimeout_s = 5.0;      // a feed hold decelerates within this

double seconds_since(std::chrono::steady_clock::time_point since) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - since).count();
}

// Control characters and bytes past ASCII as \xNN, so that noise shows as what it is.
std::string printable(std::string_view bytes) {
  std::string text;
  for (const char c : bytes) {
    const auto byte = static_cast<unsigned char>(c);
    if (byte >= 0x20 && byte < 0x7f) {
      text += c;
    } else if (c == '\n') {
      text += "\\n";
    } else if (c == '\r') {
      text += "\\r";
    } else {
      static constexpr char kHex[] = "0123456789abcdef";
      text += "\\x";
      text += kHex[byte >> 4];
      text += kHex[byte & 0xf];
    }
  }
  return text;
}

// "0.3 s", "4.0 s".
std::string seconds_text(double seconds) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f s", seconds);
  return text;
}

}  // namespace

bool writes_eeprom(std::string_view line) {
  std::string words;  // the line as grbl reads it: no spaces, no comments, upper case
  bool in_comment = false;
  for (const char c : line) {
    if (c == ';' && !in_comment) break;
    if (c == '(' || c == ')') {
      in_comment = c == '(';
    } else if (!in_comment && c != ' ' && c != '\t') {
      words += static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
  }
  if (!words.empty() && words[0] == '$') {  // $J= jogs; every other $..= is stored
    return words.find('=') != std::string::npos && words.rfind("$J=", 0) != 0;
  }
  for (std::size_t g = words.find('G'); g != std::string::npos; g = words.find('G', g + 1)) {
    std::size_t end = g + 1;
    while (end < words.size() &&
           (std::isdigit(static_cast<unsigned char>(words[end])) || words[end] == '.')) {
      ++end;
    }
    const std::string number = words.substr(g + 1, end - g - 1);
    const std::size_t first = std::min(number.find_first_not_of('0'), number.size());
    const std::string code = number.substr(first);
    if (code == "10" || code == "28.1" || code == "30.1") return true;
  }
  return false;
}

std::string describe_line(const SentLine& line) {
  if (line.program_line == 0) return "the line sent before the program: " + line.text;
  if (line.program_line < 0) return "the line sent after the program: " + line.text;
  std::string text = "line " + std::to_string(line.program_line);
  if (line.job_line > 0) text += " (job line " + std::to_string(line.job_line) + ")";
  return text + ": " + line.text;
}

GrblSender::GrblSender(int fd, std::string port, int rx_buffer_bytes, StreamTimeouts timeouts)
    : fd_(fd),
      port_(std::move(port)),
      rx_buffer_bytes_(static_cast<std::size_t>(std::max(rx_buffer_bytes, 1))),
      timeouts_(timeouts),
      last_byte_(Clock::now()),
      last_status_request_(Clock::now()) {}

void GrblSender::check_interrupted() const {
  if (interrupted_ != nullptr && *interrupted_ != 0) {
    throw StreamInterrupted(port_ + ": interrupted");
  }
}

void GrblSender::write_all(std::string_view bytes) {
  const auto start = Clock::now();
  while (!bytes.empty()) {
    const ssize_t written = ::write(fd_, bytes.data(), bytes.size());
    if (written > 0) {
      bytes.remove_prefix(static_cast<std::size_t>(written));
      continue;
    }
    if (written < 0 && errno != EAGAIN && errno != EINTR) {
      throw StreamError(port_ + ": cannot write (" + std::strerror(errno) + ")");
    }
    if (seconds_since(start) > timeouts_.silence_s) {
      throw StreamError(port_ + ": the port takes no bytes for " +
                        seconds_text(timeouts_.silence_s));
    }
    pollfd wait{fd_, POLLOUT, 0};
    ::poll(&wait, 1, 50);
  }
}

void GrblSender::pump(double wait_s) {
  pollfd wait{fd_, POLLIN, 0};
  const int ready = ::poll(&wait, 1, static_cast<int>(wait_s * 1000.0));
  if (ready <= 0) return;  // nothing yet (or a signal: the caller looks at the flag)
  char buffer[512];
  const ssize_t count = ::read(fd_, buffer, sizeof buffer);
  if (count < 0 && (errno == EAGAIN || errno == EINTR)) return;
  if (count <= 0) {
    throw StreamError(port_ + ": the port closed (" +
                      (count == 0 ? std::string("end of file") : std::strerror(errno)) +
                      "): the controller is gone");
  }
  last_byte_ = Clock::now();
  for (ssize_t i = 0; i < count; ++i) {
    const char c = buffer[i];
    if (collecting_ && received_.size() < kShownBytes) received_ += c;
    if (c == '\n') {
      const std::string line = std::exchange(partial_, {});
      handle(line);
    } else if (partial_.size() < kLongestReply) {
      partial_ += c;
    }
  }
}

void GrblSender::handle(const std::string& line) {
  Reply reply = parse_reply(line);
  switch (reply.kind) {
    case ReplyKind::ok:
      if (!in_flight_.empty()) {
        in_flight_bytes_ -= in_flight_.front().bytes;
        in_flight_.pop_front();
        ++lines_acknowledged_;
      }
      return;
    case ReplyKind::error: {
      if (in_flight_.empty()) return;  // not an answer to a line of ours (before the program)
      SentLine refused = in_flight_.front();
      in_flight_bytes_ -= refused.bytes;
      in_flight_.pop_front();
      throw GrblRefusal(port_ + ": grbl refused " + describe_line(refused) +
                            ": error:" + std::to_string(reply.code) + ": " +
                            std::string(error_meaning(reply.code)),
                        reply, refused);
    }
    case ReplyKind::alarm: {
      SentLine at = in_flight_.empty() ? SentLine{} : in_flight_.front();
      std::string where = in_flight_.empty()
                              ? std::string("after the last line")
                              : "with " + describe_line(at) + " and those before it not done";
      throw GrblRefusal(port_ + ": grbl raised ALARM:" + std::to_string(reply.code) + " (" +
                            std::string(alarm_meaning(reply.code)) + ") " + where,
                        reply, at);
    }
    case ReplyKind::status:
      if (auto status = parse_status(reply.text, work_offset_)) {
        if (status->state != "Idle" || in_flight_.empty()) {
          idle_since_.reset();
        } else if (!idle_since_) {
          idle_since_ = Clock::now();
        }
        if (status->state != "Run" || !status->has_position || in_flight_.empty()) {
          still_since_.reset();
        } else if (!still_since_ || status->work_position != still_at_) {
          still_since_ = Clock::now();
          still_at_ = status->work_position;
        }
        last_status_ = *status;
        if (on_status) on_status(*status);
      }
      return;
    case ReplyKind::banner:
      if (banner_seen_ && !in_flight_.empty()) {
        throw StreamError(port_ + ": grbl restarted (\"" + reply.text + "\") with " +
                          std::to_string(in_flight_.size()) + " lines in its buffer, the oldest " +
                          describe_line(in_flight_.front()));
      }
      banner_seen_ = true;
      return;
    case ReplyKind::message:
    case ReplyKind::other:
      if (banner_seen_ && on_message && !reply.text.empty()) on_message(reply.text);
      return;
  }
}

std::string GrblSender::what_came() const {
  if (received_.empty()) return "nothing came";
  return "it answered \"" + printable(received_) + "\"";
}

std::string GrblSender::await_banner() {
  bool reset_sent = false;
  for (int attempt = 0; attempt < 2 && !banner_seen_; ++attempt) {
    if (attempt == 1) {
      write_all("\x18");  // a grbl already running says its banner on a reset
      reset_sent = true;
    }
    const auto start = Clock::now();
    while (!banner_seen_ && seconds_since(start) < timeouts_.banner_s) {
      check_interrupted();
      pump(0.05);
    }
  }
  // The banner seen may be a late one of the start, the reset's still to come: take it too.
  for (const auto start = Clock::now(); banner_seen_ && reset_sent && seconds_since(start) < 1.0;) {
    pump(0.05);
  }
  if (!banner_seen_) {
    throw StreamError(port_ + ": no grbl banner (\"Grbl 1.1h ['$' for help]\") within " +
                      seconds_text(2 * timeouts_.banner_s) + ", a soft reset included: " +
                      what_came() + ". Is this the controller's port, at its baud rate?");
  }
  collecting_ = false;
  last_byte_ = Clock::now();
  return "grbl";
}

void GrblSender::request_status_now_and_then() {
  if (seconds_since(last_status_request_) < timeouts_.status_interval_s) return;
  write_all("?");
  last_status_request_ = Clock::now();
}

void GrblSender::check_silence() const {
  if (seconds_since(last_byte_) > timeouts_.silence_s) {
    std::string waiting = in_flight_.empty()
                              ? std::string(" (no line waiting)")
                              : " waiting for the answer to " + describe_line(in_flight_.front());
    throw StreamError(port_ + ": the controller said nothing for " +
                      seconds_text(timeouts_.silence_s) + ", asked for its status every " +
                      std::to_string(static_cast<int>(timeouts_.status_interval_s * 1000)) +
                      " ms," + waiting);
  }
}

void GrblSender::check_idle_stall() {
  if (still_since_ && seconds_since(*still_since_) >= timeouts_.idle_stall_s) {
    char where[96];
    std::snprintf(where, sizeof where, "%.3f, %.3f, %.3f", still_at_[0], still_at_[1],
                  still_at_[2]);
    throw StreamError(port_ + ": grbl reports Run, yet its position has stood at " + where +
                      " for " + seconds_text(timeouts_.idle_stall_s) + " with " +
                      std::to_string(in_flight_.size()) +
                      " lines unanswered: its stepping has stopped; the oldest line waiting is " +
                      describe_line(in_flight_.front()));
  }
  if (!idle_since_ || seconds_since(*idle_since_) < timeouts_.idle_stall_s) return;
  for (const SentLine& line : in_flight_) {
    const bool dwell =
        line.text.find("G4") != std::string::npos || line.text.find("g4") != std::string::npos;
    // A dwell of the program: grbl is idle while it waits (not drain's G4 P0, which is over
    // once the motion is).
    if (dwell && line.program_line >= 0) return;
  }
  throw StreamError(port_ + ": grbl is idle, yet " + std::to_string(in_flight_.size()) +
                    " lines sent have no answer after " + seconds_text(timeouts_.idle_stall_s) +
                    " (bytes lost on the line?), the oldest " + describe_line(in_flight_.front()));
}

void GrblSender::send(std::string_view line, long program_line, int job_line) {
  SentLine sent{std::string(line), line.size() + 1, program_line, job_line};
  if (sent.bytes > rx_buffer_bytes_) {
    throw StreamError(port_ + ": " + describe_line(sent) + " is " + std::to_string(sent.bytes) +
                      " bytes with its newline, more than grbl's receive buffer of " +
                      std::to_string(rx_buffer_bytes_));
  }
  check_interrupted();
  // A line that writes the EEPROM goes alone: an AVR grbl does not serve its serial port while
  // it writes, and would lose the bytes of the lines after it.
  const bool alone = writes_eeprom(line);
  wait_for_room(alone ? rx_buffer_bytes_ : sent.bytes);
  write_all(sent.text + "\n");
  in_flight_bytes_ += sent.bytes;
  in_flight_.push_back(std::move(sent));
  ++lines_sent_;
  pump(0.0);
  if (alone) wait_for_room(rx_buffer_bytes_);
}

void GrblSender::wait_for_room(std::size_t bytes) {
  while (!in_flight_.empty() && in_flight_bytes_ + bytes > rx_buffer_bytes_) {
    pump(timeouts_.status_interval_s / 2);
    check_interrupted();
    request_status_now_and_then();
    check_silence();
    check_idle_stall();
  }
}

void GrblSender::drain() {
  // G4 P0 is answered once grbl's planner has run every block before it: the motion is done.
  send("G4 P0", -1, 0);
  while (!in_flight_.empty()) {
    pump(timeouts_.status_interval_s / 2);
    check_interrupted();
    request_status_now_and_then();
    check_silence();
    check_idle_stall();
  }
  // The position where it stopped, for the caller. Asked again while no report comes whole: a
  // report garbled on the line (noise, a lost byte) is not the position.
  last_status_.reset();
  const auto start = Clock::now();
  while (!last_status_ && seconds_since(start) < timeouts_.silence_s) {
    write_all("?");
    const auto asked = Clock::now();
    while (!last_status_ && seconds_since(asked) < timeouts_.status_interval_s) pump(0.05);
  }
}

std::string GrblSender::hold_and_reset() {
  try {
    write_all("!");
    const auto start = Clock::now();
    std::string state;
    // Errors and alarms for lines grbl still held no longer matter: the program is abandoned.
    while (seconds_since(start) < kHoldTimeout_s) {
      last_status_.reset();
      write_all("?");
      const auto asked = Clock::now();
      while (!last_status_ && seconds_since(asked) < 0.5) {
        try {
          pump(0.05);
        } catch (const GrblRefusal&) {
        }
      }
      if (last_status_) state = last_status_->state;
      if (state == "Hold:0" || state == "Idle" || state.rfind("Alarm", 0) == 0) break;
    }
    in_flight_.clear();
    in_flight_bytes_ = 0;
    banner_seen_ = false;
    write_all("\x18");
    const auto reset = Clock::now();
    while (!banner_seen_ && seconds_since(reset) < timeouts_.banner_s) {
      try {
        pump(0.05);
      } catch (const GrblRefusal&) {
      }
    }
    std::string held =
        state.empty() ? "no status answer to the feed hold" : "feed held (grbl: " + state + ")";
    return held + (banner_seen_ ? ", then grbl was reset" : ", then no banner after the reset");
  } catch (const std::exception& error) {
    return std::string("the feed hold and reset failed: ") + error.what();
  }
}

}  // namespace pkm::stream

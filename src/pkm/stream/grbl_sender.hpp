// A sender for grbl-class controllers over an open file descriptor (a serial port, or the pty of
// grbl-sim): grbl's character counting (the bytes of the lines sent and not yet answered never
// exceed its receive buffer), its replies matched to the lines they answer, status reports asked
// for while it works, and a clean stop (feed hold, then soft reset). Every wait has a timeout;
// a line is written whole or not at all.
#pragma once

#include <array>
#include <chrono>
#include <csignal>
#include <cstddef>
#include <deque>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>

#include "pkm/stream/grbl_replies.hpp"

namespace pkm::stream {

struct StreamTimeouts {
  // From opening the port to grbl's banner (an Arduino restarts when its port opens: about 2 s);
  // the sender then resets grbl (0x18) and waits as long again.
  double banner_s = 4.0;
  // No byte at all from the controller for this long, while it is asked for its status: it is
  // gone.
  double silence_s = 5.0;
  double status_interval_s = 0.2;  // how often '?' is sent while waiting
  // grbl reporting Idle this long while lines wait for their answer (and none of them is a
  // dwell, G4): it lost part of a line and waits for a newline that will not come. And grbl
  // reporting Run this long at one position while lines wait: its stepping has stopped.
  double idle_stall_s = 5.0;
};

// A line of the program as sent: where it came from, for the messages.
struct SentLine {
  std::string text;
  std::size_t bytes = 0;  // text and its newline
  long program_line = 0;  // line of the joint program (1-based)
  int job_line = 0;       // line of the Cartesian job it was posted from (0: none)
};

// The port failed, went silent, or never answered as grbl does.
class StreamError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// grbl answered a line with error:N, or raised ALARM:N while the program ran.
class GrblRefusal : public std::runtime_error {
 public:
  GrblRefusal(const std::string& message, Reply reply, SentLine line)
      : std::runtime_error(message), reply_(std::move(reply)), line_(std::move(line)) {}
  const Reply& reply() const { return reply_; }
  const SentLine& line() const { return line_; }  // the line refused (error) or last answered

 private:
  Reply reply_;
  SentLine line_;
};

// The interrupt flag was raised (Ctrl-C) between two lines.
class StreamInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class GrblSender {
 public:
  // `fd` stays the caller's (not closed here); `port` names it in messages.
  GrblSender(int fd, std::string port, int rx_buffer_bytes, StreamTimeouts timeouts = {});

  // Raised asynchronously (a signal handler): checked between lines and while waiting.
  void set_interrupt_flag(const volatile std::sig_atomic_t* flag) { interrupted_ = flag; }
  std::function<void(const StatusReport&)> on_status;
  std::function<void(const std::string&)> on_message;  // [MSG:...] and other feedback lines

  // Waits for grbl's banner (then a soft reset and as long again); returns it. Throws
  // StreamError naming what came instead.
  std::string await_banner();
  // Sends one line once grbl's buffer has room for it; a line that writes grbl's EEPROM
  // (writes_eeprom) alone, once every line before it is answered, and waits for its answer.
  // Throws GrblRefusal at an error or alarm answered meanwhile, StreamInterrupted, StreamError.
  void send(std::string_view line, long program_line, int job_line);
  // Waits for every line's answer and for grbl to be idle.
  void drain();
  // Feed hold ('!'), until grbl has stopped (or a timeout), then soft reset (0x18) and its
  // banner: the machine stops without losing its position and grbl forgets the lines it held.
  // Never throws; returns what happened, for the user.
  std::string hold_and_reset();

  long lines_sent() const { return lines_sent_; }
  long lines_acknowledged() const { return lines_acknowledged_; }
  std::size_t bytes_in_flight() const { return in_flight_bytes_; }
  const std::optional<StatusReport>& last_status() const { return last_status_; }

 private:
  using Clock = std::chrono::steady_clock;
  // Reads what is there within `wait_s` and handles each complete line; throws at a refusal.
  void pump(double wait_s);
  // Until `bytes` more fit beside the lines not yet answered (or none is left unanswered).
  void wait_for_room(std::size_t bytes);
  void handle(const std::string& line);
  void write_all(std::string_view bytes);
  void check_interrupted() const;
  void request_status_now_and_then();
  void check_silence() const;
  void check_idle_stall();
  std::string what_came() const;

  int fd_;
  std::string port_;
  std::size_t rx_buffer_bytes_;
  StreamTimeouts timeouts_;
  const volatile std::sig_atomic_t* interrupted_ = nullptr;
  std::deque<SentLine> in_flight_;
  std::size_t in_flight_bytes_ = 0;
  std::string partial_;   // bytes of the line being received
  std::string received_;  // the first bytes received, for "answered ... instead"
  bool banner_seen_ = false;
  bool collecting_ = true;  // until the banner: keep what came, to show it
  std::array<double, 3> work_offset_{};
  std::optional<StatusReport> last_status_;
  long lines_sent_ = 0;
  long lines_acknowledged_ = 0;
  Clock::time_point last_byte_, last_status_request_;
  std::optional<Clock::time_point> idle_since_;  // status Idle with lines waiting, since
  // Status Run with lines waiting and the position standing at still_at_, since: grbl's
  // stepping has stopped (grbl-sim's clock does so at times on a busy computer).
  std::optional<Clock::time_point> still_since_;
  std::array<double, 3> still_at_{};
};

// Whether grbl writes its EEPROM for `line`: a $ setting ($100=80, $N0=..., $RST=*; not a $J=
// jog), G10, G28.1, G30.1. grbl's documentation asks senders to send such lines one at a time.
bool writes_eeprom(std::string_view line);

// "line 12 (job line 5): G1 X1.00000 Y2.00000" for messages.
std::string describe_line(const SentLine& line);

}  // namespace pkm::stream

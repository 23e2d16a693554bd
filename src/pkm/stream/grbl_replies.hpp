// What grbl 1.1 writes back to a sender (grbl's doc/markdown/interface.md): the line kinds a
// streamer has to tell apart, its real-time status reports, and what its error and alarm codes
// mean, in a sentence a plotter owner can act on.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>

namespace pkm::stream {

enum class ReplyKind {
  ok,       // "ok": the oldest line sent was done
  error,    // "error:N": the oldest line sent was refused
  alarm,    // "ALARM:N": grbl stopped; nothing more runs until it is reset or unlocked
  status,   // "<Idle|MPos:...>": answer to '?' (not a reply to a line)
  message,  // "[MSG:...]", "[GC:...]", "$N=V": feedback, not a reply to a line
  banner,   // "Grbl 1.1h ['$' for help]": grbl (re)started
  other,    // anything else: noise on the line, or not a grbl
};

struct Reply {
  ReplyKind kind = ReplyKind::other;
  int code = 0;  // N of error:N and ALARM:N
  std::string text;
};

// One line from grbl, its line ending already removed (a trailing '\r' is dropped here).
Reply parse_reply(std::string_view line);

// A status report: the state ("Idle", "Run", "Hold:0", "Alarm", ...) and the work position of
// X Y Z: the program's coordinates, for a joint program its joints in mm or deg. grbl reports
// MPos (machine position, counted from where it started or homed) or WPos ($10); the work
// position is MPos less the work offset WCO (G10 L20, G92), which grbl reports now and then.
struct StatusReport {
  std::string state;
  std::array<double, 3> work_position{};
  bool has_position = false;
};

// Parses "<...>" (nullopt for anything else or a malformed report). `work_offset` is the last
// WCO seen; it is updated when this report carries one.
std::optional<StatusReport> parse_status(std::string_view line, std::array<double, 3>& work_offset);

// What error:N and ALARM:N mean (grbl 1.1h's codes), or "an error code grbl 1.1h does not
// define" for others.
std::string_view error_meaning(int code);
std::string_view alarm_meaning(int code);

}  // namespace pkm::stream

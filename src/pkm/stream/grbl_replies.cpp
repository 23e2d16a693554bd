#include "pkm/stream/grbl_replies.hpp"

#include <charconv>
#include <cstdlib>
#include <string>

namespace pkm::stream {

namespace {

bool starts_with(std::string_view text, std::string_view prefix) {
  return text.substr(0, prefix.size()) == prefix;
}

// The N of "error:N" / "ALARM:N"; -1 when it is not a number.
int code_after(std::string_view text, std::string_view prefix) {
  const std::string_view digits = text.substr(prefix.size());
  int code = -1;
  const auto [end, status] = std::from_chars(digits.data(), digits.data() + digits.size(), code);
  if (status != std::errc() || end != digits.data() + digits.size()) return -1;
  return code;
}

// "1.000,-2.5,0" -> three numbers; false unless exactly three finite numbers.
bool three_numbers(std::string_view text, std::array<double, 3>& out) {
  std::string copy(text);
  const char* cursor = copy.c_str();
  for (int axis = 0; axis < 3; ++axis) {
    char* end = nullptr;
    out[static_cast<std::size_t>(axis)] = std::strtod(cursor, &end);
    if (end == cursor) return false;
    cursor = end;
    if (axis < 2) {
      if (*cursor != ',') return false;
      ++cursor;
    }
  }
  // grbl 1.1 reports as many numbers as axes: three here; more would be another build.
  return *cursor == '\0';
}

}  // namespace

Reply parse_reply(std::string_view line) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  Reply reply;
  reply.text = std::string(line);
  if (line == "ok") {
    reply.kind = ReplyKind::ok;
  } else if (starts_with(line, "error:") && (reply.code = code_after(line, "error:")) >= 0) {
    reply.kind = ReplyKind::error;
  } else if (starts_with(line, "ALARM:") && (reply.code = code_after(line, "ALARM:")) >= 0) {
    reply.kind = ReplyKind::alarm;
  } else if (line.size() >= 2 && line.front() == '<' && line.back() == '>') {
    reply.kind = ReplyKind::status;
  } else if (starts_with(line, "Grbl ")) {
    reply.kind = ReplyKind::banner;
  } else if ((line.size() >= 2 && line.front() == '[' && line.back() == ']') ||
             starts_with(line, "$")) {
    reply.kind = ReplyKind::message;
  } else {
    reply.code = 0;
  }
  return reply;
}

std::optional<StatusReport> parse_status(std::string_view line,
                                         std::array<double, 3>& work_offset) {
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  if (line.size() < 2 || line.front() != '<' || line.back() != '>') return std::nullopt;
  line = line.substr(1, line.size() - 2);
  StatusReport report;
  std::optional<std::array<double, 3>> machine, work;
  std::size_t start = 0;
  for (bool first = true; start <= line.size(); first = false) {
    std::size_t end = line.find('|', start);
    if (end == std::string_view::npos) end = line.size();
    const std::string_view field = line.substr(start, end - start);
    std::array<double, 3> numbers{};
    if (first) {
      report.state = std::string(field);
    } else if (starts_with(field, "MPos:")) {
      if (!three_numbers(field.substr(5), numbers)) return std::nullopt;
      machine = numbers;
    } else if (starts_with(field, "WPos:")) {
      if (!three_numbers(field.substr(5), numbers)) return std::nullopt;
      work = numbers;
    } else if (starts_with(field, "WCO:")) {
      if (!three_numbers(field.substr(4), numbers)) return std::nullopt;
      work_offset = numbers;
    }
    start = end + 1;
  }
  if (report.state.empty()) return std::nullopt;
  if (work) {
    report.work_position = *work;
    report.has_position = true;
  } else if (machine) {
    for (std::size_t axis = 0; axis < 3; ++axis) {
      report.work_position[axis] = (*machine)[axis] - work_offset[axis];
    }
    report.has_position = true;
  }
  return report;
}

std::string_view error_meaning(int code) {
  switch (code) {
    case 1:
      return "a word without its letter (G-code words are a letter and a number)";
    case 2:
      return "a number is missing or not written as a number";
    case 3:
      return "grbl does not know this '$' command";
    case 4:
      return "a value that must be positive is negative";
    case 5:
      return "homing is not enabled in grbl's settings ($22)";
    case 6:
      return "the step pulse must be at least 3 microseconds ($0)";
    case 7:
      return "grbl could not read its settings from EEPROM and restored the defaults";
    case 8:
      return "this '$' command is accepted only while grbl is idle";
    case 9:
      return "G-code is locked out while grbl is in alarm or jogging: unlock ($X) or home";
    case 10:
      return "soft limits need homing to be enabled ($20 needs $22)";
    case 11:
      return "the line is longer than grbl's 80 characters and was not run";
    case 12:
      return "this setting would make the steps faster than grbl can pulse (30 kHz)";
    case 13:
      return "the safety door is open";
    case 14:
      return "the line is too long to be stored in EEPROM";
    case 15:
      return "the jog target is beyond the machine's travel";
    case 16:
      return "the jog command has no '=' or a G-code a jog may not contain";
    case 17:
      return "laser mode needs the PWM spindle output";
    case 20:
      return "a G or M code grbl does not support";
    case 21:
      return "two commands of the same modal group on one line";
    case 22:
      return "no feed rate has been set";
    case 23:
      return "this command needs a whole number";
    case 24:
      return "two commands on the line both want the axis words";
    case 25:
      return "a word is repeated on the line";
    case 26:
      return "the command needs axis words and the line has none";
    case 27:
      return "the line number (N) is out of range";
    case 28:
      return "the command is missing a value word it needs";
    case 29:
      return "grbl has no G59.1, G59.2 or G59.3 work coordinate systems";
    case 30:
      return "G53 only works with G0 or G1";
    case 31:
      return "axis words that no command on the line uses";
    case 32:
      return "an arc (G2/G3) needs an axis word in its plane";
    case 33:
      return "the move's target is invalid (an arc that cannot be drawn, for instance)";
    case 34:
      return "the arc's radius is invalid";
    case 35:
      return "an arc (G2/G3) needs an offset word (I, J or K) in its plane";
    case 36:
      return "value words that no command on the line uses";
    case 37:
      return "G43.1 on an axis that is not the tool length axis";
    case 38:
      return "a tool number above what grbl supports";
    default:
      return "an error code grbl 1.1h does not define";
  }
}

std::string_view alarm_meaning(int code) {
  switch (code) {
    case 1:
      return "a hard limit switch tripped: the position is probably lost, home again";
    case 2:
      return "a move goes past the machine's travel (soft limits): position kept, unlock "
             "with $X";
    case 3:
      return "reset during motion: the position is probably lost, home again";
    case 4:
      return "the probe was in the wrong state when the probing cycle started";
    case 5:
      return "the probe touched nothing within the programmed travel";
    case 6:
      return "homing was stopped by a reset";
    case 7:
      return "the safety door opened during homing";
    case 8:
      return "homing could not pull off the limit switch (raise the pull-off $27, check "
             "the wiring)";
    case 9:
      return "homing found no limit switch within the search distance (check max travel "
             "$130.., the pull-off, the wiring)";
    default:
      return "an alarm code grbl 1.1h does not define";
  }
}

}  // namespace pkm::stream

#include "pkm/motion/pen_path.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace pkm::motion {

namespace {

constexpr int kPieces = 64;               // a move is searched for pen changes in this many pieces
constexpr std::size_t kMaxLevels = 4096;  // Z levels tallied; a job with more gets no suggestion
constexpr std::size_t kListedLevels = 4;  // listed one by one in a warning, else as a range

// Whether the move's Z changes along it (an arc or a blend may come back to where it started).
bool moves_in_z(const Segment& segment) {
  for (const double u : {0.25, 0.5, 0.75, 1.0}) {
    if (segment.at(u)[2] != segment.start[2]) return true;
  }
  return false;
}

// Whether the move goes anywhere in X or Y.
bool moves_in_xy(const Segment& segment) {
  for (const double u : {0.5, 1.0}) {
    if (segment.at(u).head<2>() != segment.start.head<2>()) return true;
  }
  return false;
}

// A length as a user reads it: up to 4 decimals, no trailing zeros.
std::string number_text(double value) {
  char text[48];
  std::snprintf(text, sizeof text, "%.4f", value);
  std::string s = text;
  while (s.back() == '0') s.pop_back();
  if (s.back() == '.') s.pop_back();
  return s == "-0" ? "0" : s;
}

// Z levels as text, ascending: "0, 65 and 90", or "12 levels from 0 to 90".
std::string list_text(const std::vector<double>& levels) {
  if (levels.size() > kListedLevels) {
    return std::to_string(levels.size()) + " levels from " + number_text(levels.front()) + " to " +
           number_text(levels.back());
  }
  std::string s;
  for (std::size_t i = 0; i < levels.size(); ++i) {
    if (i > 0) s += i + 1 == levels.size() ? " and " : ", ";
    s += number_text(levels[i]);
  }
  return s;
}

}  // namespace

PenPath::PenPath(const machine::Machine& machine)
    : tool_(machine.tool()), mm_per_unit_(machine.mm_per_unit()), unit_(machine.length_unit()) {}

namespace {

// The fractions of the move (in order) where its Z passes from one side of the pen's height to
// the other, each the first point on the new side: 64 pieces, each bisected, so a move whose Z
// goes down and up again (an arc in XZ) shows both.
std::vector<double> side_changes(const Segment& segment, const machine::ToolChannel& tool) {
  const auto down_at = [&](double u) { return tool.pen_down(segment.at(u)[2]); };
  std::vector<double> changes;
  bool down = down_at(0.0);
  for (int k = 1; k <= kPieces; ++k) {
    double low = static_cast<double>(k - 1) / kPieces, high = static_cast<double>(k) / kPieces;
    if (down_at(high) == down) continue;
    for (int i = 0; i < 60; ++i) {
      const double middle = 0.5 * (low + high);
      (down_at(middle) == down ? low : high) = middle;
    }
    down = !down;
    changes.push_back(high);
  }
  return changes;
}

}  // namespace

std::vector<PenChange> PenPath::follow(const Segment& segment) {
  std::vector<PenChange> changes;
  if (!follows_z_ && moves_in_z(segment)) follows_z_ = true;
  follows_from_ = follows_z_ ? 0.0 : kNever;
  if (follows_z_) {
    std::vector<double> sides = side_changes(segment, tool_);
    bool down = tool_.pen_down(segment.start[2]);
    // Only at the job's first move in Z can the pen (up) and the Z (home's, on the drawing side)
    // disagree: a move that leaves the drawing side (the job lifting its pen first) leaves the
    // pen up until the Z comes back; one that stays on it puts the pen down at its start.
    if (down != down_) {
      if (!sides.empty()) {
        follows_from_ = sides.front();
        sides.erase(sides.begin());
      } else {
        changes.push_back({0.0, true});
      }
      down = down_;
    }
    for (const double u : sides) {
      down = !down;
      changes.push_back({u, down});
    }
  }
  for (const PenChange& change : changes) {
    if (change.down) {
      if (downs_ == 0) first_down_line_ = segment.line;
      ++downs_;
    } else if (downs_ > 0) {
      ++ups_after_down_;
    }
    down_ = change.down;
  }
  tally(segment);
  return changes;
}

void PenPath::tally(const Segment& segment) {
  const double z = std::round(segment.end[2] * 1e4) / 1e4;
  if (!moves_in_xy(segment)) {
    if (z_only_levels_.size() < kMaxLevels) z_only_levels_.insert(z);
    return;
  }
  if (first_xy_line_ == 0) first_xy_line_ = std::max(segment.line, 1);
  if (down_) {
    if (drawn_level_ && *drawn_level_ != z) drew_at_two_levels_ = true;
    drawn_level_ = z;
  }
  auto level = levels_.find(z);
  if (level == levels_.end()) {
    if (levels_.size() >= kMaxLevels) {
      levels_overflow_ = true;
      return;
    }
    level = levels_.emplace(z, ZLevelMoves{}).first;
  }
  ++(segment.rapid ? level->second.rapid : level->second.feed);
}

std::string PenPath::levels_text() const {
  std::vector<double> feed, rapid, both;
  for (const auto& [z, moves] : levels_) {
    const double value = z / mm_per_unit_;
    (moves.feed > 0 && moves.rapid > 0 ? both : moves.feed > 0 ? feed : rapid).push_back(value);
  }
  std::string s;
  const auto add = [&](const std::vector<double>& levels, const char* what) {
    if (levels.empty()) return;
    if (!s.empty()) s += ", ";
    s += list_text(levels) + " " + unit_ + what;
  };
  add(feed, " (feed)");
  add(rapid, " (rapid)");
  add(both, " (feed and rapid)");
  if (levels_overflow_) s += ", and more";
  std::vector<double> z_only;
  for (const double z : z_only_levels_) {
    if (!levels_.contains(z)) z_only.push_back(z / mm_per_unit_);
  }
  if (!z_only.empty()) s += ", its moves in Z alone to Z " + list_text(z_only) + " " + unit_;
  return s;
}

// The [tool] height that separates where the job draws from where it travels: its feed moves
// from its rapids where the two keep apart, else the Z of most feed moves from every other.
std::string PenPath::suggestion() const {
  std::vector<double> feed, rapid;
  double busiest = 0.0;
  long most = -1;
  for (const auto& [z, moves] : levels_) {
    if (moves.feed > 0) feed.push_back(z);
    if (moves.rapid > 0) rapid.push_back(z);
    if (moves.feed > most) {
      most = moves.feed;
      busiest = z;
    }
  }
  if (levels_overflow_ || levels_.size() < 2 || feed.empty()) return "";
  std::vector<double> draw, travel;
  if (!rapid.empty() && (feed.back() < rapid.front() || feed.front() > rapid.back())) {
    draw = feed;
    travel = rapid;
  } else {
    draw = {busiest};
    for (const auto& [z, moves] : levels_) {
      if (z != busiest) travel.push_back(z);
    }
    if (!(travel.front() > busiest || travel.back() < busiest)) return "";
  }
  const bool above = draw.front() > travel.back();
  const double height =
      above ? 0.5 * (travel.back() + draw.front()) : 0.5 * (draw.back() + travel.front());
  const auto in_units = [&](std::vector<double> levels) {
    for (double& z : levels) z /= mm_per_unit_;
    return list_text(levels);
  };
  return "; [tool] " + std::string(above ? "down_above" : "down_below") + " = " +
         number_text(height / mm_per_unit_) + " would draw at Z " + in_units(draw) +
         " and lift the pen at Z " + in_units(travel);
}

std::optional<gcode::Warning> PenPath::warning() const {
  if (first_xy_line_ == 0) return std::nullopt;
  const std::string setting = "the pen draws " + std::string(tool_.down_above ? "above" : "below") +
                              " Z " + number_text(tool_.pen_height_mm / mm_per_unit_) + " " +
                              unit_ + " ([tool] " + tool_.height_key() + ")";
  if (downs_ == 0 && !follows_z_) {
    return gcode::Warning{first_xy_line_,
                          "the pen never goes down: the job never moves in Z (its moves run at Z " +
                              levels_text() +
                              "), and a plotter's pen is up until the job's first move in Z"};
  }
  if (downs_ == 0) {
    return gcode::Warning{first_xy_line_,
                          "the pen never goes down: the job's moves in X and Y run "
                          "at Z " +
                              levels_text() + "; " + setting + suggestion()};
  }
  if (ups_after_down_ == 0 && drew_at_two_levels_) {
    return gcode::Warning{first_down_line_,
                          "the pen goes down here and never comes up: the job's moves in X and Y "
                          "run at Z " +
                              levels_text() + "; " + setting + suggestion()};
  }
  return std::nullopt;
}

}  // namespace pkm::motion

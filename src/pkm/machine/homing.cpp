#include "pkm/machine/homing.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include "pkm/machine/machine.hpp"

namespace pkm::machine {

namespace {

// As the joint limits: a kilometre, or that many degrees.
constexpr double kMaxDistance = 1e6;
// Feeds per minute: as [cartesian] max_feed.
constexpr double kMinFeed = 1e-3, kMaxFeed = 6e7;
// The back-off when the table gives none: 5 mm (5 deg for a rotary joint).
constexpr double kDefaultBackoff_mm = 5.0;

// A number of the [homing] table within [low, high] (low itself refused unless `zero_ok`).
double bounded(const kinematics::ModelConfig& section, std::string_view key, double low,
               double high, const std::string& unit, bool zero_ok = false) {
  const double value = section.number(key);
  const bool above_low = zero_ok ? value >= low : value > low;
  if (!(above_low && value <= high)) {
    section.fail(key, std::string("must be ") + (zero_ok ? "at least " : "greater than ") +
                          kinematics::formatted_number("%g", low) + " and at most " +
                          kinematics::formatted_number("%g", high) + " " + unit + ", not " +
                          kinematics::formatted_number("%g", value));
  }
  return value;
}

int joint_named(const std::vector<JointSpec>& joints, const std::string& name) {
  for (std::size_t i = 0; i < joints.size(); ++i) {
    if (joints[i].name == name) return static_cast<int>(i);
  }
  return -1;
}

std::string joint_list(const std::vector<JointSpec>& joints) {
  std::string names;
  for (const JointSpec& joint : joints) names += (names.empty() ? "" : ", ") + joint.name;
  return names;
}

std::vector<int> read_sequence(const kinematics::ModelConfig& section,
                               const std::vector<JointSpec>& joints,
                               const std::vector<bool>& passthrough) {
  std::vector<int> sequence;
  for (const std::string& name : section.string_list("sequence")) {
    const int joint = joint_named(joints, name);
    if (joint < 0) {
      section.fail("sequence", "names '" + name + "', which is no joint of the machine (" +
                                   joint_list(joints) + ")");
    }
    if (std::find(sequence.begin(), sequence.end(), joint) != sequence.end()) {
      section.fail("sequence", "names joint '" + name + "' twice");
    }
    if (!joints[static_cast<std::size_t>(joint)].home_switch) {
      section.fail("sequence", "names joint '" + name +
                                   "', whose [[joints]] table has no home_switch (the joint "
                                   "reading at which its switch trips)");
    }
    sequence.push_back(joint);
  }
  if (sequence.empty()) section.fail("sequence", "names no joint");
  for (std::size_t i = 0; i < joints.size(); ++i) {
    const bool named =
        std::find(sequence.begin(), sequence.end(), static_cast<int>(i)) != sequence.end();
    if (!passthrough[i] && !named) {
      section.fail("sequence", "leaves out joint '" + joints[i].name +
                                   "': every joint of the mechanism must find its switch, or "
                                   "the pose is unknown at the end");
    }
  }
  return sequence;
}

bool any_of_kind(const std::vector<JointSpec>& joints, const std::vector<int>& sequence,
                 kinematics::JointKind kind) {
  return std::any_of(sequence.begin(), sequence.end(),
                     [&](int j) { return joints[static_cast<std::size_t>(j)].kind == kind; });
}

// Units of the [homing] table's numbers, as its joints read them.
std::string table_unit(const std::vector<JointSpec>& joints, const std::vector<int>& sequence,
                       double mm_per_unit) {
  const bool rotary = any_of_kind(joints, sequence, kinematics::JointKind::rotary);
  const std::string length = mm_per_unit == 1.0 ? "mm" : "in";
  if (rotary && any_of_kind(joints, sequence, kinematics::JointKind::linear)) {
    return length + " (deg for rotary joints)";
  }
  return rotary ? "deg" : length;
}

// The procedure's moves with the failures of `fail(key, message)`; `home` the home pose's joints.
class HomingPlanner {
 public:
  HomingPlanner(const Machine& machine, const HomingTable& table,
                std::function<void(std::string_view, const std::string&)> fail)
      : machine_(machine), table_(table), fail_(std::move(fail)) {
    const std::size_t count = machine.joints().size();
    known_.assign(count, std::nullopt);
    payouts_.assign(count, 0);
  }

  std::vector<HomingMove> plan(const kinematics::JointVector& home) {
    for (const int joint : table_.sequence) home_joint(joint);
    HomingMove go_home{HomingMoveKind::go_home, -1, {}, 0.0, 0.0};
    for (const int joint : table_.sequence) go_home.targets.emplace_back(joint, home[joint]);
    go_home.feed_per_min = feed_at_interface(table_.sequence.front(), table_.feed);
    moves_.push_back(go_home);
    return moves_;
  }

 private:
  const JointSpec& spec(int joint) const {
    return machine_.joints()[static_cast<std::size_t>(joint)];
  }
  bool passthrough(int joint) const { return machine_.kinematics().passthrough_axis(joint) >= 0; }
  // A distance or position of the table in the joint's units (mm, rad).
  double internal(int joint, double file_value) const {
    return machine_.joint_from_file(joint, file_value);
  }
  double feed_at_interface(int joint, double file_feed) const {
    return spec(joint).to_interface(internal(joint, file_feed));
  }
  std::string shown(int joint, double internal_value) const {
    return machine_.joint_value_text(joint, internal_value);
  }

  void home_joint(int joint) {
    if (!passthrough(joint) && table_.slack > 0.0) pay_out_others(joint);
    const HomeSwitch& home_switch = *spec(joint).home_switch;
    const double direction = home_switch.toward_max ? 1.0 : -1.0;
    const double travel = table_.probe_travel ? internal(joint, *table_.probe_travel)
                                              : default_travel(joint, home_switch.position);
    const double speed = internal(joint, table_.probe_feed) / 60.0;
    moves_.push_back({HomingMoveKind::probe,
                      joint,
                      {{joint, direction * travel}},
                      feed_at_interface(joint, table_.probe_feed),
                      speed * speed / (2.0 * spec(joint).max_acceleration)});
    known_[static_cast<std::size_t>(joint)] = home_switch.position;
    moves_.push_back(
        {HomingMoveKind::set_position, joint, {{joint, home_switch.position}}, 0.0, 0.0});
    const double backoff = internal(joint, table_.backoff);
    const double after = home_switch.position - direction * backoff;
    if (!(after >= spec(joint).min && after <= spec(joint).max)) fail_backoff(joint, backoff);
    known_[static_cast<std::size_t>(joint)] = after;
    moves_.push_back({HomingMoveKind::back_off,
                      joint,
                      {{joint, -direction * backoff}},
                      feed_at_interface(joint, table_.feed),
                      0.0});
  }

  // The back-off must leave the joint within its limits: say which back-offs would.
  [[noreturn]] void fail_backoff(int joint, double backoff) const {
    const HomeSwitch& home_switch = *spec(joint).home_switch;
    const double away = home_switch.toward_max ? -1.0 : 1.0;  // direction of the back-off
    const double after = home_switch.position + away * backoff;
    const double to_min = away * (spec(joint).min - home_switch.position);
    const double to_max = away * (spec(joint).max - home_switch.position);
    const double shortest = std::max(0.0, std::min(to_min, to_max));
    const double longest = std::max(to_min, to_max);
    std::string advice = "no back-off can: move home_switch within reach of the limits";
    if (longest > shortest) {
      advice = "give a backoff between " + shown(joint, shortest) + " and " + shown(joint, longest);
    }
    fail_("backoff", "backing off " + shown(joint, backoff) + " from the switch of joint '" +
                         spec(joint).name + "' (home_switch " + shown(joint, home_switch.position) +
                         ") leaves it outside its limits: " + machine_.explain_joint(joint, after) +
                         "; " + advice);
    throw std::logic_error("fail_ returned");
  }

  void pay_out_others(int homed) {
    HomingMove move{HomingMoveKind::pay_out, homed, {}, 0.0, 0.0};
    for (int joint = 0; joint < static_cast<int>(machine_.joints().size()); ++joint) {
      if (joint == homed || passthrough(joint)) continue;
      const double slack = internal(joint, table_.slack);
      move.targets.emplace_back(joint, slack);
      auto& known = known_[static_cast<std::size_t>(joint)];
      if (!known) {
        ++payouts_[static_cast<std::size_t>(joint)];
        continue;
      }
      *known += slack;
      if (*known > spec(joint).max) {
        fail_("slack",
              "paying out joint '" + spec(joint).name + "' by " + shown(joint, slack) +
                  " before joint '" + spec(homed).name +
                  "' homes takes it past its max: " + machine_.explain_joint(joint, *known) +
                  "; give a smaller slack, or home '" + spec(joint).name + "' later");
      }
    }
    if (move.targets.empty()) return;
    move.feed_per_min = feed_at_interface(move.targets.front().first, table_.feed);
    moves_.push_back(move);
  }

  // As far as the joint can be from its switch within its limits, plus the slack earlier steps
  // paid it out by while its position was unknown.
  double default_travel(int joint, double switch_position) const {
    const double farthest = std::max(std::abs(switch_position - spec(joint).min),
                                     std::abs(switch_position - spec(joint).max));
    return farthest + payouts_[static_cast<std::size_t>(joint)] * internal(joint, table_.slack);
  }

  const Machine& machine_;
  const HomingTable& table_;
  std::function<void(std::string_view, const std::string&)> fail_;
  std::vector<std::optional<double>> known_;  // positions after their switch (mm, rad)
  std::vector<int> payouts_;                  // slack paid out while unknown
  std::vector<HomingMove> moves_;
};

}  // namespace

std::optional<HomeSwitch> read_home_switch(const kinematics::ModelConfig& table,
                                           const JointSpec& joint, double scale) {
  if (!table.has("home_switch")) {
    if (table.has("home_toward")) table.fail("home_toward", "needs home_switch beside it");
    return std::nullopt;
  }
  const double value = table.number("home_switch");
  if (!(std::abs(value) <= kMaxDistance)) {
    table.fail("home_switch",
               "must be within 1e+06 of 0, not " + kinematics::formatted_number("%g", value));
  }
  HomeSwitch home_switch;
  home_switch.position = value * scale;
  // By default the switch is at the end of the travel it is nearer: a switch near min is reached
  // by pulling the cable in.
  home_switch.toward_max = home_switch.position - joint.min > joint.max - home_switch.position;
  if (table.has("home_toward")) {
    const std::string toward = table.string("home_toward");
    if (toward != "min" && toward != "max") {
      table.fail("home_toward", "must be \"min\" or \"max\", not \"" + toward + "\"");
    }
    home_switch.toward_max = toward == "max";
  }
  return home_switch;
}

HomingTable read_homing_table(const kinematics::ModelConfig& section,
                              const std::vector<JointSpec>& joints,
                              const std::vector<bool>& passthrough, double mm_per_unit) {
  HomingTable table;
  table.sequence = read_sequence(section, joints, passthrough);
  const std::string unit = table_unit(joints, table.sequence, mm_per_unit);
  table.slack = bounded(section, "slack", 0.0, kMaxDistance, unit, true);
  table.probe_feed = bounded(section, "probe_feed", kMinFeed, kMaxFeed, unit + "/min", true);
  if (section.has("feed")) {
    table.feed = bounded(section, "feed", kMinFeed, kMaxFeed, unit + "/min", true);
  } else {
    // As fast as the slowest homed joint may go, in the file's units per minute.
    table.feed = kMaxFeed;
    for (const int j : table.sequence) {
      const JointSpec& joint = joints[static_cast<std::size_t>(j)];
      const double per_s = joint.kind == kinematics::JointKind::rotary
                               ? joint.to_interface(joint.max_velocity)
                               : joint.max_velocity / mm_per_unit;
      table.feed = std::min(table.feed, 60.0 * per_s);
    }
  }
  const bool only_rotary = !any_of_kind(joints, table.sequence, kinematics::JointKind::linear);
  table.backoff = section.has("backoff")
                      ? bounded(section, "backoff", 0.0, kMaxDistance, unit)
                      : (only_rotary ? kDefaultBackoff_mm : kDefaultBackoff_mm / mm_per_unit);
  if (section.has("probe_travel")) {
    table.probe_travel = bounded(section, "probe_travel", 0.0, 2.0 * kMaxDistance, unit);
  }
  return table;
}

std::vector<HomingMove> homing_moves(const Machine& machine,
                                     const kinematics::ModelConfig* section) {
  if (!machine.homing()) {
    throw std::invalid_argument(machine.source() +
                                ": the machine file has no [homing] table (docs/homing.md)");
  }
  kinematics::JointVector home;
  const kinematics::Status status = machine.inverse(machine.home(), home);
  if (!status.ok()) {
    throw std::invalid_argument(machine.source() +
                                ": home is not usable: " + machine.explain(machine.home(), status));
  }
  HomingPlanner planner(machine, *machine.homing(),
                        [&](std::string_view key, const std::string& message) {
                          if (section != nullptr) section->fail(key, message);
                          throw std::invalid_argument(machine.source() + ": [homing] " +
                                                      std::string(key) + ": " + message);
                        });
  return planner.plan(home);
}

}  // namespace pkm::machine

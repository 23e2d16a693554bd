#include "pkm/controller/grbl_planner.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <limits>
#include <stdexcept>

namespace pkm::controller {

namespace {

constexpr double kMinimumFeedPerS = 1.0 / 60.0;  // grbl's MINIMUM_FEED_RATE, 1 mm/min
constexpr double kStraight = 0.999999;           // |cos| past which grbl calls a junction straight
constexpr double kBitsPerByte = 10.0;            // 8N1: start, 8 data bits, stop
constexpr double kNever = std::numeric_limits<double>::infinity();

// The motion of the executing block from its current speed over what remains of it: up (or down)
// to `peak`, a cruise, down to `exit`, all at `acceleration`.
struct Profile {
  double start = 0.0, peak = 0.0, exit = 0.0, acceleration = 0.0;
  double ramp = 0.0, cruise = 0.0, down = 0.0;  // lengths of the three phases

  Profile(double entry, double length, double a, double nominal, double exit_speed)
      : start(entry), exit(exit_speed), acceleration(a) {
    const double peak_sqr = 0.5 * (entry * entry + exit_speed * exit_speed) + a * length;
    if (entry * entry >= exit_speed * exit_speed + 2.0 * a * length) {
      // Too fast to reach the exit speed (the plan never asks this; rounding may): down all the
      // way.
      peak = entry;
      exit = std::sqrt(std::max(0.0, entry * entry - 2.0 * a * length));
      down = length;
      return;
    }
    peak = std::min(nominal, std::sqrt(peak_sqr));
    if (entry > nominal) peak = nominal;
    ramp = std::abs(peak * peak - entry * entry) / (2.0 * a);
    down = std::max(0.0, (peak * peak - exit * exit) / (2.0 * a));
    cruise = std::max(0.0, length - ramp - down);
  }
  double ramp_s() const { return std::abs(peak - start) / acceleration; }
  double cruise_s() const { return peak > 0.0 ? cruise / peak : 0.0; }
  double down_s() const { return (peak - exit) / acceleration; }
  double time_s() const { return ramp_s() + cruise_s() + down_s(); }

  // Distance and speed `dt` (< time_s()) after the start.
  void after(double dt, double& distance, double& speed) const {
    if (dt < ramp_s()) {
      const double a = peak >= start ? acceleration : -acceleration;
      speed = start + a * dt;
      distance = start * dt + 0.5 * a * dt * dt;
      return;
    }
    dt -= ramp_s();
    if (dt < cruise_s()) {
      speed = peak;
      distance = ramp + peak * dt;
      return;
    }
    dt -= cruise_s();
    speed = std::max(exit, peak - acceleration * dt);
    distance = ramp + cruise + peak * dt - 0.5 * acceleration * dt * dt;
  }
};

// The smallest of limit[i] / |direction[i]| over the axes the direction moves: how fast (or how
// hard) the block may go along it without one axis passing its own limit.
double limited_by_axes(const std::vector<double>& limit, const std::vector<double>& direction) {
  double value = kNever;
  for (std::size_t i = 0; i < limit.size(); ++i) {
    if (direction[i] != 0.0) value = std::min(value, limit[i] / std::abs(direction[i]));
  }
  return value;
}

std::invalid_argument line_error(std::string_view line, const std::string& what) {
  return std::invalid_argument("grbl model: " + what + " in \"" + std::string(line) + "\"");
}

}  // namespace

GrblSetup grbl_setup_of(const machine::Machine& machine) {
  if (!machine.controller()) {
    throw std::invalid_argument(machine.source() + ": no [controller] table: nothing to model");
  }
  GrblSetup setup;
  setup.settings = *machine.controller();
  for (const machine::JointSpec& joint : machine.joints()) {
    if (!joint.steps_per_unit) {
      throw std::invalid_argument(machine.source() + ": joint '" + joint.name +
                                  "' has no steps_per_unit, which its [controller] needs");
    }
    setup.axes.push_back({joint.axis_letter, *joint.steps_per_unit,
                          joint.to_interface(joint.max_velocity),
                          joint.to_interface(joint.max_acceleration)});
  }
  kinematics::JointVector home;
  if (!machine.inverse(machine.home(), home).ok()) {
    throw std::invalid_argument(machine.source() + ": home has no joint values to start from");
  }
  for (std::size_t i = 0; i < machine.joints().size(); ++i) {
    setup.start.push_back(machine.joints()[i].to_interface(home[static_cast<Eigen::Index>(i)]));
  }
  return setup;
}

double trapezoid_time_s(double length, double acceleration, double entry, double nominal,
                        double exit) {
  return Profile(entry, length, acceleration, nominal, exit).time_s();
}

double planned_time_s(std::vector<GrblTimeModel::Block> blocks) {
  if (blocks.empty()) return 0.0;
  double exit_sqr = 0.0;
  for (std::size_t i = blocks.size(); i-- > 0;) {
    GrblTimeModel::Block& block = blocks[i];
    block.entry_sqr =
        std::min(block.max_entry_sqr, exit_sqr + 2.0 * block.acceleration * block.length);
    exit_sqr = block.entry_sqr;
  }
  blocks.front().entry_sqr = 0.0;
  for (std::size_t i = 0; i + 1 < blocks.size(); ++i) {
    const GrblTimeModel::Block& block = blocks[i];
    blocks[i + 1].entry_sqr = std::min(blocks[i + 1].entry_sqr,
                                       block.entry_sqr + 2.0 * block.acceleration * block.length);
  }
  double time_s = 0.0;
  for (std::size_t i = 0; i < blocks.size(); ++i) {
    const double exit = i + 1 < blocks.size() ? std::sqrt(blocks[i + 1].entry_sqr) : 0.0;
    time_s += trapezoid_time_s(blocks[i].length, blocks[i].acceleration,
                               std::sqrt(blocks[i].entry_sqr), blocks[i].nominal, exit);
  }
  return time_s;
}

GrblTimeModel::GrblTimeModel(GrblSetup setup)
    : setup_(std::move(setup)),
      byte_s_(kBitsPerByte / setup_.settings.baud),
      capacity_(static_cast<std::size_t>(setup_.settings.planner_blocks) - 1),
      target_(setup_.axes.size(), 0.0),
      position_steps_(setup_.axes.size(), 0),
      previous_unit_(setup_.axes.size(), 0.0) {
  if (!setup_.start.empty()) {
    if (setup_.start.size() != setup_.axes.size()) {
      throw std::invalid_argument("grbl model: a start position for each axis, or none");
    }
    target_ = setup_.start;
    for (std::size_t i = 0; i < target_.size(); ++i) {
      position_steps_[i] = std::lround(target_[i] * setup_.axes[i].steps_per_unit);
    }
  }
  if (setup_.settings.baud <= 0 || setup_.settings.planner_blocks < 2 ||
      setup_.settings.rx_buffer_bytes < 1 || setup_.settings.junction_deviation < 0.0) {
    throw std::invalid_argument("grbl model: impossible controller settings");
  }
  for (const GrblAxis& axis : setup_.axes) {
    if (!(axis.steps_per_unit > 0.0 && axis.max_rate > 0.0 && axis.max_acceleration > 0.0)) {
      throw std::invalid_argument(std::string("grbl model: axis ") + axis.letter +
                                  " needs positive steps, rate and acceleration");
    }
  }
}

// When the last byte of a line of `bytes` (its newline included) has arrived: the sender starts
// it once the line is free and the receive buffer has room for it beside the lines grbl has not
// yet answered (character counting).
double GrblTimeModel::arrival_of(std::size_t bytes) {
  const auto limit = static_cast<std::size_t>(setup_.settings.rx_buffer_bytes);
  if (bytes > limit) {
    throw std::invalid_argument("grbl model: a line of " + std::to_string(bytes) +
                                " bytes does not fit grbl's receive buffer of " +
                                std::to_string(limit));
  }
  double start = line_free_s_;
  std::size_t waiting = 0;
  for (const Sent& sent : in_flight_) waiting += sent.bytes;
  while (!in_flight_.empty() && (in_flight_.front().ack_s <= start || waiting + bytes > limit)) {
    start = std::max(start, in_flight_.front().ack_s);
    waiting -= in_flight_.front().bytes;
    in_flight_.pop_front();
  }
  line_free_s_ = start + static_cast<double>(bytes) * byte_s_;
  return line_free_s_;
}

void GrblTimeModel::read_words(std::string_view line, bool& motion, bool& sync, double& dwell_s) {
  std::size_t i = 0;
  bool dwell = false;
  auto skip = [&] {
    while (i < line.size()) {
      const char c = line[i];
      if (c == '(') {
        const std::size_t close = line.find(')', i);
        i = close == std::string_view::npos ? line.size() : close + 1;
      } else if (c == ';' || c == '%') {
        i = line.size();
      } else if (std::isspace(static_cast<unsigned char>(c))) {
        ++i;
      } else {
        return;
      }
    }
  };
  for (skip(); i < line.size(); skip()) {
    const char letter = static_cast<char>(std::toupper(static_cast<unsigned char>(line[i++])));
    std::size_t end = i;
    while (end < line.size() && (std::isdigit(static_cast<unsigned char>(line[end])) ||
                                 line[end] == '.' || line[end] == '-' || line[end] == '+')) {
      ++end;
    }
    double value = 0.0;
    const char* first = line.data() + i + (i < end && line[i] == '+' ? 1 : 0);
    if (std::from_chars(first, line.data() + end, value).ec != std::errc() ||
        first == line.data() + end) {
      throw line_error(line, std::string("no number after ") + letter);
    }
    i = end;
    const auto axis = std::find_if(setup_.axes.begin(), setup_.axes.end(),
                                   [&](const GrblAxis& a) { return a.letter == letter; });
    if (axis != setup_.axes.end()) {
      target_[static_cast<std::size_t>(axis - setup_.axes.begin())] = value;
      motion = true;
    } else if (letter == 'G') {
      if (value == 0.0 || value == 1.0) {
        rapid_ = value == 0.0;
      } else if (value == 93.0 || value == 94.0) {
        inverse_time_ = value == 93.0;
      } else if (value == 4.0) {
        dwell = true;
      } else if (value != 21.0 && value != 90.0 && value != 17.0) {
        sync = true;  // what else post passes on (offsets, G10): waited for, to be safe
      }
    } else if (letter == 'F') {
      feed_ = value;
    } else if (letter == 'P' && dwell) {
      dwell_s = value;
    } else if (letter == 'M' || letter == 'S') {
      sync = true;  // spindle, coolant and program flow wait for the planner to empty
    } else if (letter != 'N') {
      sync = true;
    }
  }
  if (dwell) {
    sync = true;
    motion = false;
  }
}

void GrblTimeModel::add_line(std::string_view line, int tag) {
  ++prediction_.lines;
  line_tag_ = tag;
  bool motion = false, sync = false;
  double dwell_s = 0.0;
  read_words(line, motion, sync, dwell_s);
  const double arrived_s = arrival_of(line.size() + 1);
  const double processed_s = std::max(arrived_s, processed_s_);
  advance(processed_s, 0);
  if (sync) {
    wait_for_stop();
    flush_unlimited();
    now_s_ += dwell_s;
    prediction_.unlimited_time_s += dwell_s;
  }
  if (motion) {
    if (!rapid_ && feed_ <= 0.0) throw line_error(line, "a feed move with no F");
    if (buffer_.size() >= capacity_) advance(kNever, capacity_);
    plan_move();
  }
  processed_s_ = now_s_;
  in_flight_.push_back({now_s_, line.size() + 1});
}

void GrblTimeModel::plan_move() {
  const std::size_t n = setup_.axes.size();
  std::vector<double> unit(n), rates(n), accelerations(n);
  std::vector<long> target_steps(n);
  double length_sqr = 0.0;
  for (std::size_t i = 0; i < n; ++i) {
    const GrblAxis& axis = setup_.axes[i];
    target_steps[i] = std::lround(target_[i] * axis.steps_per_unit);
    unit[i] = static_cast<double>(target_steps[i] - position_steps_[i]) / axis.steps_per_unit;
    length_sqr += unit[i] * unit[i];
    rates[i] = axis.max_rate;
    accelerations[i] = axis.max_acceleration;
  }
  if (target_steps == position_steps_) return;  // grbl plans no block for a move of no step
  const double length = std::sqrt(length_sqr);
  for (double& u : unit) u /= length;
  Block block;
  block.length = length;
  block.acceleration = limited_by_axes(accelerations, unit);
  const double rapid_rate = limited_by_axes(rates, unit);
  const double programmed = rapid_ ? rapid_rate : (inverse_time_ ? feed_ * length : feed_) / 60.0;
  block.nominal = std::max(kMinimumFeedPerS, std::min(programmed, rapid_rate));
  double junction_sqr = 0.0;  // from rest where the planner is empty
  if (!buffer_.empty()) {
    double cos_theta = 0.0;
    std::vector<double> bisector(n);
    double bisector_sqr = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
      cos_theta -= previous_unit_[i] * unit[i];
      bisector[i] = unit[i] - previous_unit_[i];
      bisector_sqr += bisector[i] * bisector[i];
    }
    if (cos_theta > kStraight) {
      junction_sqr = 0.0;  // a reversal: grbl's MINIMUM_JUNCTION_SPEED, 0
    } else if (cos_theta < -kStraight) {
      junction_sqr = kNever;
    } else {
      for (double& b : bisector) b /= std::sqrt(bisector_sqr);
      const double sin_half = std::sqrt(0.5 * (1.0 - cos_theta));
      junction_sqr = limited_by_axes(accelerations, bisector) * setup_.settings.junction_deviation *
                     sin_half / (1.0 - sin_half);
    }
  }
  block.max_entry_sqr = std::min(
      {junction_sqr, block.nominal * block.nominal, previous_nominal_ * previous_nominal_});
  previous_nominal_ = block.nominal;
  previous_unit_ = unit;
  position_steps_ = target_steps;
  if (!started_) {
    started_ = true;
    prediction_.motion_start_s = now_s_;
  }
  if (unlimited_.empty()) {
    stretch_tag_ = line_tag_;
    stretch_start_s_ = now_s_;
  }
  ++prediction_.blocks;
  prediction_.path_length += length;
  acceleration_length_ += block.acceleration * length;
  unlimited_.push_back(block);
  buffer_.push_back(block);
  recalculate();
}

// grbl's two passes over the buffer: back from the newest block (which ends at rest), each entry
// no faster than what decelerates to the next; then forward from the executing block at its
// current speed, each entry no faster than what accelerates from the one before.
void GrblTimeModel::recalculate() {
  const std::size_t n = buffer_.size();
  buffer_.front().entry_sqr = speed_ * speed_;
  if (n < 2) return;
  double exit_sqr = 0.0;
  for (std::size_t i = n - 1; i >= 1; --i) {
    Block& block = buffer_[i];
    block.entry_sqr =
        std::min(block.max_entry_sqr, exit_sqr + 2.0 * block.acceleration * block.length);
    exit_sqr = block.entry_sqr;
  }
  for (std::size_t i = 0; i + 1 < n; ++i) {
    const Block& block = buffer_[i];
    buffer_[i + 1].entry_sqr = std::min(buffer_[i + 1].entry_sqr,
                                        block.entry_sqr + 2.0 * block.acceleration * block.length);
  }
}

void GrblTimeModel::advance(double until_s, std::size_t keep) {
  while (!buffer_.empty() && buffer_.size() >= keep && now_s_ < until_s) {
    Block& block = buffer_.front();
    const double exit = buffer_.size() > 1 ? std::sqrt(buffer_[1].entry_sqr) : 0.0;
    const Profile profile(speed_, block.length, block.acceleration, block.nominal, exit);
    const double duration_s = profile.time_s();
    if (now_s_ + duration_s <= until_s) {
      now_s_ += duration_s;
      speed_ = profile.exit;
      buffer_.pop_front();
      if (!buffer_.empty()) buffer_.front().entry_sqr = speed_ * speed_;
      continue;
    }
    double distance = 0.0;
    profile.after(until_s - now_s_, distance, speed_);
    block.length = std::max(block.length - distance, 0.0);
    block.entry_sqr = speed_ * speed_;
    now_s_ = until_s;
  }
  if (buffer_.empty()) {
    speed_ = 0.0;
    if (until_s != kNever) now_s_ = std::max(now_s_, until_s);
  }
}

void GrblTimeModel::wait_for_stop() {
  advance(kNever, 1);
}

// At a stop (the machine at rest, now_s_ its time): the stretch since the last stop with every
// block known, against what the look-ahead and the line made of it.
void GrblTimeModel::flush_unlimited() {
  if (unlimited_.empty()) return;
  const double unlimited_s = planned_time_s(std::move(unlimited_));
  unlimited_.clear();
  prediction_.unlimited_time_s += unlimited_s;
  const double lost_s = now_s_ - stretch_start_s_ - unlimited_s;
  if (lost_s > prediction_.slowest_stretch_lost_s) {
    prediction_.slowest_stretch_lost_s = lost_s;
    prediction_.slowest_stretch_tag = stretch_tag_;
  }
}

GrblPrediction GrblTimeModel::finish() {
  wait_for_stop();
  flush_unlimited();
  prediction_.time_s = now_s_;
  if (prediction_.path_length > 0.0) {
    prediction_.mean_acceleration = acceleration_length_ / prediction_.path_length;
  }
  return prediction_;
}

}  // namespace pkm::controller

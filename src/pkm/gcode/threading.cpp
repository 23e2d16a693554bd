// G76, LinuxCNC's threading cycle, expanded into passes as rs274 expands it: each pass comes in
// to its depth along X (Z moved by the compound angle Q), cuts along Z synchronised with the
// spindle at the pitch P (with 45-degree-like tapers in and out at a steeper pitch when E and L
// ask), and goes back out; the depths grow by J times the pass number to the power 1/R until
// the full depth K, which is cut H + 1 times. The thread runs along Z and cuts along X whatever
// the plane (a lathe's). The number of passes is bounded before any is made.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "pkm/gcode/interpreter_state.hpp"

namespace pkm::gcode {

// One G76 block's geometry, program units. Depths are measured along X from `start_x` (the
// drive line), inwards for a thread on the outside, outwards when boring.
struct ThreadPasses {
  double start_x = 0.0, start_z = 0.0;
  bool boring = false;      // I > 0: an inside thread
  double i_depth = 0.0;     // |I|: the drive line to the thread's crest
  double first_cut = 0.0;   // |J|
  double full_depth = 0.0;  // |K|: the thread's height
  double pitch = 0.0;       // P, per revolution
  double tan_angle = 0.0;   // tan Q, signed by the direction of the cut
  double degression = 1.0;  // R
  double taper = 0.0;       // E along Z, signed by the direction of the cut
  double taper_pitch = 0.0;
  bool taper_in = false, taper_out = false;  // L bits 1 and 2
  double target_z = 0.0;
  long full_depth_passes = 1;  // H + 1 (none for a negative H, as rs274)
  int column = 1;

  // X at `depth` from the drive line.
  double x_at(double depth) const { return boring ? start_x + depth : start_x - depth; }
  double end_depth() const { return full_depth + i_depth; }
};

ThreadPasses Interpreter::State::thread_passes(const Block& block, const Position& end) const {
  ThreadPasses t;
  t.column = move_column;
  const double i = block.value('i'), j = block.value('j'), k = block.value('k');
  if (i == 0.0) fail(block.word('i')->column, "in G76, I (the thread's offset) must not be 0");
  if (!(j > 0.0)) fail(block.word('j')->column, "in G76, J (the first cut) must be above 0");
  if (!(k > j)) fail(block.word('k')->column, "in G76, K (the full depth) must be above J");
  t.start_x = pos[kX];
  t.start_z = pos[kZ];
  t.boring = i > 0.0;
  t.i_depth = std::abs(i);
  t.first_cut = std::abs(j);
  t.full_depth = std::abs(k);
  t.pitch = block.value('p');
  const bool towards_plus_z = end[kZ] > t.start_z;
  const double angle = (block.has('q') ? block.value('q') : 0.0) * std::numbers::pi / 180.0;
  t.tan_angle = std::tan(towards_plus_z ? -angle : angle);
  t.degression = block.has('r') ? std::max(1.0, block.value('r')) : 1.0;
  t.taper = block.has('e') ? std::max(0.0, block.value('e')) : 0.0;
  t.taper_pitch = t.taper > 0.0 ? t.pitch * std::hypot(t.taper, t.full_depth) / t.taper : t.pitch;
  if (towards_plus_z) t.taper = -t.taper;
  const long flags = block.has('l') ? std::lround(block.value('l')) : 0;
  t.taper_in = (flags & 1) != 0;
  t.taper_out = (flags & 2) != 0;
  t.target_z = end[kZ] + t.full_depth * t.tan_angle;
  const long spring = block.has('h') ? std::lround(block.value('h')) : 0;
  t.full_depth_passes = std::max(0L, spring + 1);
  return t;
}

void Interpreter::State::require_thread_words(const Block& block, const Position& end) const {
  for (int axis = 3; axis < kAxes; ++axis) {
    if (end[axis] != pos[axis]) {
      fail(move_column, "cannot move the rotary or U V W axes with G76 (a thread runs in X Z)");
    }
  }
  const double most = static_cast<double>(options.max_loop_iterations);
  for (const char letter : {'h', 'l'}) {
    const auto& word = block.word(letter);
    if (word && word->value != std::floor(word->value)) {
      fail(word->column, std::string(1, static_cast<char>(std::toupper(letter))) +
                             " must be a whole number with G76");
    }
  }
  require_word_in_range(block, 'h', -most, most,
                        "G76's spring passes (the bound on one loop) go from");
  require_word_in_range(block, 'l', 0.0, 3.0, "G76's taper flags go from");
}

void Interpreter::State::threading_cycle(const Block& block, const Position& end) {
  require_turning_spindle(760);
  require_thread_words(block, end);
  const ThreadPasses t = thread_passes(block, end);
  // The passes short of the full depth are those of J n^(1/R) < K: n < (K/J)^R, known before
  // any is made (a tiny J or a large R would make billions).
  const double passes = std::pow(t.full_depth / t.first_cut, t.degression);
  const double most = static_cast<double>(options.max_loop_iterations);
  if (!(passes + static_cast<double>(t.full_depth_passes) <= most)) {
    fail(t.column, "G76 would make more than " + std::to_string(options.max_loop_iterations) +
                       " passes (the bound on one loop): (K/J)^R is " + written_number(passes));
  }
  double depth = t.i_depth + t.first_cut;
  for (long pass = 1; depth < t.end_depth(); ++pass) {
    threading_pass(block, t, depth);
    depth = t.i_depth + t.first_cut * std::pow(static_cast<double>(pass + 1), 1.0 / t.degression);
  }
  for (long pass = 0; pass < t.full_depth_passes; ++pass) threading_pass(block, t, t.end_depth());
  Position last = pos;
  for (const int axis : {kX, kY, kZ}) last[axis] = end[axis];
  straight(CanonKind::traverse, block, last);
}

void Interpreter::State::threading_pass(const Block& block, const ThreadPasses& t, double depth) {
  count_program_iteration(t.column);
  const double z_offset = (depth - t.i_depth) * t.tan_angle;
  const double start_z = t.start_z - z_offset, end_z = t.target_z - z_offset;
  const auto to = [&](double x, double z) {
    Position p = pos;
    p[kX] = x;
    p[kZ] = z;
    return p;
  };
  const auto feed_override = [&](bool enabled) {
    Canon c = make(CanonKind::feed_override, block);
    c.integer = enabled ? 1 : 0;
    emit(c);
  };
  const double out_x = t.x_at(depth - t.end_depth());  // clear of the thread
  const double crest_x = t.x_at(depth - t.full_depth);
  straight(CanonKind::traverse, block, to(out_x, start_z));
  if (t.taper != 0.0 && t.taper_in) {
    feed_override(false);
    start_synchronisation(block, t.taper_pitch);
    synchronised_feed(block, to(crest_x, start_z), t.taper_pitch);
    synchronised_feed(block, to(t.x_at(depth), start_z - t.taper), t.taper_pitch);
    start_synchronisation(block, t.pitch);
  } else {
    straight(CanonKind::traverse, block, to(t.x_at(depth), start_z));
    feed_override(false);
    start_synchronisation(block, t.pitch);
  }
  if (t.taper != 0.0 && t.taper_out) {
    synchronised_feed(block, to(t.x_at(depth), end_z + t.taper), t.pitch);
    start_synchronisation(block, t.taper_pitch);
    synchronised_feed(block, to(crest_x, end_z), t.taper_pitch);
  } else {
    synchronised_feed(block, to(t.x_at(depth), end_z), t.pitch);
  }
  emit(CanonKind::speed_feed_sync_stop, block);
  straight(CanonKind::traverse, block, to(out_x, end_z));
  feed_override(true);
}

}  // namespace pkm::gcode

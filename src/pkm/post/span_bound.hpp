// The deviation bound of a joint-linear block that spans several consecutive programmed moves (a
// run of short lines and arcs): the bound of deviation_bound.hpp for the straight chord between
// the block's programmed ends, plus how far the programmed path strays from that chord at the
// same fraction (docs/post.md, "Spanning moves").
#pragma once

#include <cmath>
#include <cstddef>
#include <vector>

#include "pkm/motion/segment.hpp"
#include "pkm/post/deviation_bound.hpp"

namespace pkm::post {

// The stretch [from, to] (fractions) of one programmed move that a covering takes in.
struct Piece {
  motion::Segment segment;
  double from = 0.0, to = 1.0;
};

// The programmed path one block stands for: from fraction `start` of the first piece's move,
// through the pieces in order, to fraction `end` of the last one's (the pieces between are taken
// whole, from their `from` to their `to`).
struct Span {
  const Piece* pieces = nullptr;
  std::size_t count = 0;
  double start = 0.0, end = 1.0;

  const Piece& first() const { return pieces[0]; }
  const Piece& last() const { return pieces[count - 1]; }
  // The fractions of piece k's move the span covers.
  double from(std::size_t k) const { return k == 0 ? start : pieces[k].from; }
  double to(std::size_t k) const { return k + 1 == count ? end : pieces[k].to; }
  geometry::Vector6d start_pose() const { return first().segment.at(start); }
  geometry::Vector6d end_pose() const { return last().segment.at(end); }
  // Seconds the programmed path takes at its programmed feeds, its rapids at `rapid_mm_per_s`.
  double programmed_s(double rapid_mm_per_s) const;
  // The programmed path's length (mm).
  double length_mm() const;
};

// An upper bound (mm) on the distance, in the position coordinates among `axes`, between the
// straight chord from the span's start to its end and the programmed path, each point of the
// path against the chord's point at a matching fraction (a reparametrisation that never goes
// back): the largest distance of a vertex (the ends of the pieces) from the chord at its
// projection's fraction, plus the largest sagitta bound of an arc piece. Infinity where the path
// turns back along the chord (a vertex behind the one before or beyond the chord's end, a curved
// piece heading back anywhere, a chord of no length): no span is taken across a turn back.
double chord_offset_mm(const Span& span, const std::vector<int>& axes, double angle_scale_mm);

// An upper bound (mm) on the distance between the tool tip of the joint-linear block with
// `ends` and the programmed path of `span`, each point of one against the other's at a matching
// fraction (so both ways, and in order): for one piece, `bound` itself; for several, `bound` on
// the chord between the span's ends plus chord_offset_mm. Infinity where there is none, and
// where the chord offset alone exceeds `give_up_above_mm` (a corner: the bound of the chord, the
// costly part, is then not worked out).
double span_deviation_bound(const DeviationBound& bound, const Span& span, const BlockEnds& ends,
                            double give_up_above_mm = INFINITY);

}  // namespace pkm::post

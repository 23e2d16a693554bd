// Numbers as decimal text, fast and digit for digit as printf writes them: "%.<N>f" (fixed with
// N decimals) and "%d". The text outputs (`pkm gcode --canon`, CSV samples) format a million
// numbers a second; snprintf spends ~150 ns on each, these ~10 ns.
#pragma once

#include <cstddef>
#include <string_view>

#include "pkm/text/text_buffer.hpp"

namespace pkm::text {

// The longest text write_fixed makes: a sign, 309 integer digits (DBL_MAX), a point, 9 decimals.
inline constexpr std::size_t kMaxFixedChars = 1 + 309 + 1 + 9;

// Writes `value` as printf's "%.<Decimals>f" does in the default rounding mode: the exact binary
// value rounded to `Decimals` places, an exact tie to the even digit; "-" whenever the sign bit is
// set (so -0.0 and -0.00001 give "-0.0000"); "inf", "-inf", "nan", "-nan". Returns the end of the
// text; `out` has room for kMaxFixedChars. Decimals 0..9.
template <int Decimals>
char* write_fixed(char* out, double value);

// printf's "%d"; `out` has room for 24 characters.
char* write_int(char* out, long value);

template <int Decimals>
void append_fixed(TextBuffer& out, double value) {
  out.commit(write_fixed<Decimals>(out.room(kMaxFixedChars), value));
}

inline void append_int(TextBuffer& out, long value) {
  out.commit(write_int(out.room(24), value));
}

// printf's "%<width>d": right-aligned, padded with spaces on the left.
void append_int_right(TextBuffer& out, long value, std::size_t width);

// printf's "%-<width>s": left-aligned, padded with spaces on the right.
void append_left(TextBuffer& out, std::string_view text, std::size_t width);

}  // namespace pkm::text

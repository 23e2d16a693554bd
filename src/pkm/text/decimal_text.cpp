#include "pkm/text/decimal_text.hpp"

#include <bit>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>

namespace pkm::text {

namespace {

// GCC's and Clang's 128-bit integer (__extension__: not ISO C++, but on every target built).
__extension__ typedef unsigned __int128 Uint128;

constexpr std::uint64_t kPowersOfTen[] = {1,      10,      100,      1000,      10000,
                                          100000, 1000000, 10000000, 100000000, 1000000000};

// "00".."99": two digits per step halves the divisions.
constexpr char kDigitPairs[] =
    "00010203040506070809101112131415161718192021222324252627282930313233343536373839"
    "40414243444546474849505152535455565758596061626364656667686970717273747576777879"
    "8081828384858687888990919293949596979899";

// Writes the `count` lowest decimal digits of `value`, zero-padded, ending at `end`.
void write_digits_backwards(char* end, std::uint64_t value, int count) {
  for (; count >= 2; count -= 2) {
    std::memcpy(end -= 2, kDigitPairs + 2 * (value % 100), 2);
    value /= 100;
  }
  if (count == 1) *--end = static_cast<char>('0' + value % 10);
}

char* write_unsigned(char* out, std::uint64_t value) {
  return std::to_chars(out, out + 20, value).ptr;
}

// The value times 10^Decimals rounded to an integer as printf rounds it, when the product fits in
// 64 bits; false for the rest (huge, infinite, NaN), which take the slow exact path.
template <int Decimals>
bool scaled(double value, std::uint64_t& result) {
  constexpr std::uint64_t scale = kPowersOfTen[Decimals];
  // Below 1e18 the product of the value by the scale fits in 64 bits with room for rounding up.
  constexpr double limit = 1e18 / static_cast<double>(scale);
  const double magnitude = value < 0 ? -value : value;
  if (!(magnitude < limit)) return false;  // also NaN
  const auto bits = std::bit_cast<std::uint64_t>(value);
  const int biased_exponent = static_cast<int>((bits >> 52) & 0x7ff);
  const std::uint64_t fraction = bits & ((std::uint64_t{1} << 52) - 1);
  // value = mantissa * 2^-shift exactly.
  const std::uint64_t mantissa =
      biased_exponent == 0 ? fraction : fraction | (std::uint64_t{1} << 52);
  const int shift = 1075 - (biased_exponent == 0 ? 1 : biased_exponent);
  if (shift <= 0) {  // an integer below the limit
    result = (mantissa << -shift) * scale;
    return true;
  }
  // Beyond 2^-100 times the mantissa (< 2^53) the value is below 2^-47, far under half a unit
  // of the last decimal (5e-10 at 9 decimals): zero.
  if (shift >= 100) {
    result = 0;
    return true;
  }
  // mantissa * scale < 2^53 * 2^30: exact in 128 bits.
  const Uint128 product = static_cast<Uint128>(mantissa) * scale;
  std::uint64_t quotient = static_cast<std::uint64_t>(product >> shift);
  const Uint128 remainder = product & ((static_cast<Uint128>(1) << shift) - 1);
  const Uint128 half = static_cast<Uint128>(1) << (shift - 1);
  if (remainder > half || (remainder == half && (quotient & 1) != 0)) ++quotient;
  result = quotient;
  return true;
}

}  // namespace

template <int Decimals>
char* write_fixed(char* out, double value) {
  static_assert(Decimals >= 0 && Decimals <= 9);
  std::uint64_t units = 0;
  if (!scaled<Decimals>(value, units)) {
    // std::to_chars is exact too (and spells infinities and NaNs as printf does), only slower.
    return std::to_chars(out, out + kMaxFixedChars, value, std::chars_format::fixed, Decimals).ptr;
  }
  if (std::signbit(value)) *out++ = '-';
  constexpr std::uint64_t scale = kPowersOfTen[Decimals];
  out = write_unsigned(out, units / scale);
  if constexpr (Decimals > 0) {
    *out++ = '.';
    out += Decimals;
    write_digits_backwards(out, units % scale, Decimals);
  }
  return out;
}

template char* write_fixed<0>(char*, double);
template char* write_fixed<1>(char*, double);
template char* write_fixed<2>(char*, double);
template char* write_fixed<3>(char*, double);
template char* write_fixed<4>(char*, double);
template char* write_fixed<5>(char*, double);
template char* write_fixed<6>(char*, double);
template char* write_fixed<7>(char*, double);
template char* write_fixed<8>(char*, double);
template char* write_fixed<9>(char*, double);

char* write_int(char* out, long value) {
  return std::to_chars(out, out + 24, value).ptr;
}

void append_int_right(TextBuffer& out, long value, std::size_t width) {
  char digits[24];
  const auto length = static_cast<std::size_t>(write_int(digits, value) - digits);
  if (length < width) out.append(width - length, ' ');
  out.append(std::string_view(digits, length));
}

void append_left(TextBuffer& out, std::string_view text, std::size_t width) {
  out.append(text);
  if (text.size() < width) out.append(width - text.size(), ' ');
}

}  // namespace pkm::text

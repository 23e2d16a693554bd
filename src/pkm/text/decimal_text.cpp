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

// Digits of an integer part: how many, then written backwards two at a time (a division by a
// constant is a multiplication; pairs halve them).
int decimal_digits(std::uint64_t value) {
  int digits = 1;
  for (; value >= 10000; value /= 10000) digits += 4;
  return digits + (value >= 10) + (value >= 100) + (value >= 1000);
}

// Writes `value` ending at `end` in its decimal_digits; returns where the digits start.
char* write_backwards(char* end, std::uint64_t value) {
  for (; value >= 100; value /= 100) std::memcpy(end -= 2, kDigitPairs + 2 * (value % 100), 2);
  if (value >= 10) {
    std::memcpy(end -= 2, kDigitPairs + 2 * value, 2);
  } else {
    *--end = static_cast<char>('0' + value);
  }
  return end;
}

// Writes `value` (< 10^Digits) as exactly `Digits` digits, zero-padded. Without a division per
// pair: value / 10^(Digits - lead) as a 57-bit fixed-point number, whose integer part is the
// leading digit (or pair) and whose fraction, times 100, gives the next pair, and so on. The
// multiplier is rounded up; its error, value * 10^(Digits - lead) < 2^57 units for Digits <= 9,
// never reaches the next digit.
template <int Digits>
void write_exact_digits(char* out, std::uint64_t value) {
  static_assert(Digits >= 1 && Digits <= 9);
  if constexpr (Digits <= 2) {
    if constexpr (Digits == 1) *out = static_cast<char>('0' + value);
    if constexpr (Digits == 2) std::memcpy(out, kDigitPairs + 2 * value, 2);
  } else {
    constexpr int kLead = Digits % 2 == 0 ? 2 : 1;
    constexpr int kBits = 57;
    constexpr std::uint64_t kOne = std::uint64_t{1} << kBits;
    constexpr std::uint64_t kDivisor = kPowersOfTen[Digits - kLead];
    constexpr std::uint64_t kMultiplier = (kOne + kDivisor - 1) / kDivisor;
    std::uint64_t fixed = value * kMultiplier;
    if constexpr (kLead == 1) {
      *out++ = static_cast<char>('0' + (fixed >> kBits));
    } else {
      std::memcpy(out, kDigitPairs + 2 * (fixed >> kBits), 2);
      out += 2;
    }
    for (int pair = 0; pair < (Digits - kLead) / 2; ++pair, out += 2) {
      fixed = (fixed & (kOne - 1)) * 100;
      std::memcpy(out, kDigitPairs + 2 * (fixed >> kBits), 2);
    }
  }
}

// std::to_chars is exact too (and spells infinities and NaNs as printf does), only slower.
[[gnu::noinline]] char* write_fixed_slowly(char* out, double value, int decimals) {
  return std::to_chars(out, out + kMaxFixedChars, value, std::chars_format::fixed, decimals).ptr;
}

// product / 2^shift (shift 1..127) rounded to the nearest integer, an exact tie to the even one.
[[gnu::noinline]] std::uint64_t round_shifted(Uint128 product, int shift) {
  const auto quotient = static_cast<std::uint64_t>(product >> shift);
  const Uint128 remainder = product & ((static_cast<Uint128>(1) << shift) - 1);
  const Uint128 half = static_cast<Uint128>(1) << (shift - 1);
  return quotient + ((remainder > half) | ((remainder == half) & (quotient & 1)));
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
  if (shift >= 64) {  // below 2^-11: rare
    result = round_shifted(product, shift);
    return true;
  }
  // The same in 64-bit halves, for the values jobs hold.
  const auto low = static_cast<std::uint64_t>(product);
  const auto high = static_cast<std::uint64_t>(product >> 64);
  const std::uint64_t quotient = (high << (64 - shift)) | (low >> shift);
  const std::uint64_t discarded = low << (64 - shift);  // left-aligned: 2^63 is half a unit
  constexpr std::uint64_t kHalf = std::uint64_t{1} << 63;
  result = quotient + ((discarded > kHalf) | ((discarded == kHalf) & (quotient & 1)));
  return true;
}

}  // namespace

template <int Decimals>
char* write_fixed(char* out, double value) {
  static_assert(Decimals >= 0 && Decimals <= 9);
  if (value == 0.0) {  // a third of the numbers a job prints (A B C, offsets): "0.0000"
    constexpr char kZero[] = "-0.000000000";
    const bool negative = std::signbit(value);
    std::memcpy(out, kZero + !negative, 12);  // room for kMaxFixedChars
    return out + negative + (Decimals > 0 ? Decimals + 2 : 1);
  }
  std::uint64_t units = 0;
  if (!scaled<Decimals>(value, units)) {
    return write_fixed_slowly(out, value, Decimals);
  }
  *out = '-';
  out += std::signbit(value);
  constexpr std::uint64_t scale = kPowersOfTen[Decimals];
  const std::uint64_t integer_part = units / scale;
  char* const end = out + decimal_digits(integer_part) + (Decimals > 0 ? Decimals + 1 : 0);
  if constexpr (Decimals > 0) {
    write_exact_digits<Decimals>(end - Decimals, units % scale);
    end[-Decimals - 1] = '.';
    write_backwards(end - Decimals - 1, integer_part);
  } else {
    write_backwards(end, integer_part);
  }
  return end;
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
  *out = '-';
  out += value < 0;
  // The magnitude in unsigned arithmetic, where that of LONG_MIN fits.
  const std::uint64_t magnitude =
      value < 0 ? 0 - static_cast<std::uint64_t>(value) : static_cast<std::uint64_t>(value);
  char* const end = out + decimal_digits(magnitude);
  write_backwards(end, magnitude);
  return end;
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

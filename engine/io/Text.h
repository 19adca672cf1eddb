#pragma once
// Numbers as Firn's messages write them: one value through a printf pattern ("%.3g s"), the shortest text that reads
// back as the same double, six significant digits for derived values, and counts with thousands separators
// ("97,336,000"), so that a count of particles reads at a glance.
#include <algorithm>
#include <charconv>
#include <cstdio>
#include <iterator>
#include <string>

namespace firn {

inline std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// Shortest text that reads back as the same double ("0.1", not "0.10000000000000001"): a value as a user wrote it.
inline std::string formatNumber(double value) {
  char text[32];
  const auto result = std::to_chars(std::begin(text), std::end(text), value);
  return std::string(text, result.ptr);
}

// Six significant digits, for values derived from what a user wrote (bounds, one frame's duration), where the last
// bits of a sum like 0.8 - 0.2 = 0.6000000000000001 are noise to the reader.
inline std::string formatApproximately(double value) { return format("%.6g", value); }

// `value` (at least 0) to the nearest whole number, in groups of three digits: an estimate such as 1.15³ / 0.01³ ×
// 64, which rounding puts a hair under 97,336,000, reads as that.
inline std::string withThousands(double value) {
  std::string digits = format("%.0f", std::max(0.0, value));
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(std::size_t(i), ",");
  return digits;
}

}  // namespace firn

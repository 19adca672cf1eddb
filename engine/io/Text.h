#pragma once
// Numbers as Firn's messages write them: one value through a printf pattern ("%.3g s"), and counts with thousands
// separators ("97,336,000"), so that a count of particles reads at a glance.
#include <algorithm>
#include <cstdio>
#include <string>

namespace firn {

inline std::string format(const char* pattern, double value) {
  char text[64];
  std::snprintf(text, sizeof text, pattern, value);
  return text;
}

// `value` (at least 0) to the nearest whole number, in groups of three digits: an estimate such as 1.15³ / 0.01³ ×
// 64, which rounding puts a hair under 97,336,000, reads as that.
inline std::string withThousands(double value) {
  std::string digits = format("%.0f", std::max(0.0, value));
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(std::size_t(i), ",");
  return digits;
}

}  // namespace firn

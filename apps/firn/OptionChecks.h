#pragma once
// The command line's checks on option values, with messages a user reads: CLI11's own print a range's bounds with
// std::to_string (DBL_MAX as 310 digits) and a choice's map as its internals. Each returns "" or the problem,
// which CLI11 prefixes with the option's name.
#include <cerrno>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "io/Text.h"

namespace firn::cli {

// The number `text` holds, or why not.
inline bool readNumber(const std::string& text, double& value, std::string& problem) {
  char* end = nullptr;
  errno = 0;
  value = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size()) {
    problem = "expected a number (got " + text + ")";
    return false;
  }
  if (errno == ERANGE) {
    problem = "is beyond the range of a double (got " + text + ")";
    return false;
  }
  return true;
}

// A number greater than 0.
inline CLI::Validator positive() {
  return CLI::Validator(
      [](std::string& text) {
        double value = 0;
        std::string problem;
        if (!readNumber(text, value, problem)) return problem;
        return value > 0 ? std::string() : "must be greater than 0 (got " + text + ")";
      },
      "> 0");
}

// A number in [low, high], the bounds written as a person would ("1,000,000", "0.001").
inline CLI::Validator inRange(double low, double high) {
  const auto write = [](double bound) {
    return bound == double(static_cast<long long>(bound)) && bound >= 1e4 ? withThousands(bound) : format("%g", bound);
  };
  const std::string range = "[" + write(low) + ", " + write(high) + "]";
  return CLI::Validator(
      [low, high, range](std::string& text) {
        double value = 0;
        std::string problem;
        if (!readNumber(text, value, problem)) return problem;
        return value >= low && value <= high ? std::string() : "must be in " + range + " (got " + text + ")";
      },
      range);
}

// One of `names`, in any case; the value becomes the name as listed.
inline CLI::Validator oneOf(const std::vector<std::string>& names) {
  std::string listed;
  for (const std::string& name : names) listed += (listed.empty() ? "" : ", ") + name;
  return CLI::Validator(
      [names, listed](std::string& text) {
        for (const std::string& name : names) {
          if (CLI::detail::to_lower(text) == name) {
            text = name;
            return std::string();
          }
        }
        return "must be one of " + listed + " (got " + text + ")";
      },
      "{" + listed + "}");
}

// One of a map's names, in any case; the value becomes the mapped enum's number, which CLI11 converts to the enum.
template <typename Enum>
CLI::Validator oneOf(const std::map<std::string, Enum>& choices) {
  std::vector<std::string> names;
  for (const auto& choice : choices) names.push_back(choice.first);
  const CLI::Validator name = oneOf(names);
  return CLI::Validator(
      [name, choices](std::string& text) {
        std::string problem = name(text);
        if (problem.empty()) text = std::to_string(static_cast<long long>(choices.at(text)));
        return problem;
      },
      name.get_description());
}

}  // namespace firn::cli

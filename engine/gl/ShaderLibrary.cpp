#include "gl/ShaderLibrary.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "Error.h"

namespace firn::gl {

ShaderLibrary::ShaderLibrary() : files_(embeddedShaderFiles()) {}

ShaderLibrary::ShaderLibrary(std::map<std::string, std::string> files) : files_(std::move(files)) {}

void ShaderLibrary::add(const std::string& path, std::string text) { files_[path] = std::move(text); }

namespace {

// Returns the quoted path of an `#include "path"` line, or an empty string.
std::string includedPath(const std::string& line) {
  static const std::regex includeLine(R"(^\s*#\s*include\s+"([^"]+)\"\s*$)");
  std::smatch match;
  return std::regex_match(line, match, includeLine) ? match[1].str() : std::string();
}

bool isVersionLine(const std::string& line) {
  static const std::regex versionLine(R"(^\s*#\s*version\b.*)");
  return std::regex_match(line, versionLine);
}

}  // namespace

PreprocessedShader ShaderLibrary::preprocess(const std::string& path, const ShaderOptions& options) const {
  const auto file = files_.find(path);
  if (file == files_.end()) throw GLError("shader file not found: " + path);
  std::istringstream lines(file->second);
  std::string versionLine;
  std::getline(lines, versionLine);
  if (!isVersionLine(versionLine)) throw GLError(path + ":1: a shader must start with #version");

  PreprocessedShader out;
  out.sourceNames.push_back("<injected>");
  out.text = versionLine + "\n";
  for (const auto& extension : options.extensions) out.text += "#extension " + extension + " : require\n";
  for (const auto& [name, value] : options.defines) out.text += "#define " + name + " " + value + "\n";
  std::vector<std::string> included;
  append(path, /*skipVersionLine=*/true, out, included);
  return out;
}

void ShaderLibrary::append(const std::string& path, bool skipVersionLine, PreprocessedShader& out,
                           std::vector<std::string>& included) const {
  included.push_back(path);
  const std::string sourceIndex = std::to_string(out.sourceNames.size());
  out.sourceNames.push_back(path);
  std::istringstream lines(files_.at(path));
  std::string line;
  int lineNumber = 0;
  if (skipVersionLine) {
    std::getline(lines, line);
    lineNumber = 1;
  }
  out.text += "#line " + std::to_string(lineNumber + 1) + " " + sourceIndex + "\n";
  while (std::getline(lines, line)) {
    ++lineNumber;
    const std::string include = includedPath(line);
    if (include.empty()) {
      out.text += line + "\n";
      continue;
    }
    if (files_.count(include) == 0) {
      throw GLError(path + ":" + std::to_string(lineNumber) + ": included file not found: " + include);
    }
    // Each file is included once, as if every shared file had an include guard.
    if (std::find(included.begin(), included.end(), include) != included.end()) continue;
    append(include, /*skipVersionLine=*/false, out, included);
    out.text += "#line " + std::to_string(lineNumber + 1) + " " + sourceIndex + "\n";
  }
}

std::string ShaderLibrary::translateLog(const std::string& log, const PreprocessedShader& shader) {
  static const std::regex location(R"((^|\n)\s*(\d+)(?::(\d+)\(\d+\)|\((\d+)\)))");
  std::string result;
  auto begin = log.cbegin();
  std::smatch match;
  while (std::regex_search(begin, log.cend(), match, location)) {
    const std::size_t sourceIndex = std::stoul(match[2].str());
    const std::string line = match[3].matched ? match[3].str() : match[4].str();
    result.append(begin, match[0].first);
    result += match[1].str();
    result += sourceIndex < shader.sourceNames.size() ? shader.sourceNames[sourceIndex] : match[2].str();
    result += ":" + line;
    begin = match[0].second;
  }
  result.append(begin, log.cend());
  return result;
}

}  // namespace firn::gl

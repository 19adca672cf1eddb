#include "gl/ShaderLibrary.h"

#include <algorithm>
#include <regex>
#include <sstream>

#include "Error.h"

namespace firn::gl {

ShaderLibrary::ShaderLibrary() : files_(embeddedShaderFiles()) {}

ShaderLibrary::ShaderLibrary(std::map<std::string, std::string> files) : files_(std::move(files)) {}

void ShaderLibrary::add(const std::string& path, std::string text) { files_[path] = std::move(text); }

const std::string& ShaderLibrary::file(const std::string& path) const {
  const auto found = files_.find(path);
  if (found == files_.end()) throw GLError("shader file not found: " + path);
  return found->second;
}

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

namespace {

void appendLine(PreprocessedShader& out, const std::string& text, const std::string& file, int line) {
  out.text += text + "\n";
  out.origins.push_back({file, line});
}

}  // namespace

PreprocessedShader ShaderLibrary::preprocess(const std::string& path, const ShaderOptions& options) const {
  const auto file = files_.find(path);
  if (file == files_.end()) throw GLError("shader file not found: " + path);
  const std::string& text = file->second;
  const std::string versionLine = text.substr(0, text.find('\n'));
  if (!isVersionLine(versionLine)) throw GLError(path + ":1: a shader must start with #version");

  PreprocessedShader out;
  appendLine(out, versionLine, path, 1);
  int injected = 0;
  for (const auto& extension : options.extensions) {
    appendLine(out, "#extension " + extension + " : require", "<injected>", ++injected);
  }
  for (const auto& [name, value] : options.defines) {
    appendLine(out, "#define " + name + " " + value, "<injected>", ++injected);
  }
  std::vector<std::string> included;
  append(path, out, included);
  return out;
}

void ShaderLibrary::append(const std::string& path, PreprocessedShader& out, std::vector<std::string>& included) const {
  included.push_back(path);
  std::istringstream lines(files_.at(path));
  std::string line;
  int lineNumber = 0;
  while (std::getline(lines, line)) {
    ++lineNumber;
    if (lineNumber == 1 && isVersionLine(line)) continue;  // already first in the output
    const std::string include = includedPath(line);
    if (include.empty()) {
      appendLine(out, line, path, lineNumber);
      continue;
    }
    if (files_.count(include) == 0) {
      throw GLError(path + ":" + std::to_string(lineNumber) + ": included file not found: " + include);
    }
    // Each file is included once, as if every shared file had an include guard.
    if (std::find(included.begin(), included.end(), include) == included.end()) append(include, out, included);
  }
}

std::string ShaderLibrary::translateLog(const std::string& log, const PreprocessedShader& shader) {
  static const std::regex location(R"((^|\n)\s*\d+(?::(\d+)\(\d+\)|\((\d+)\)))");
  std::string result;
  auto begin = log.cbegin();
  std::smatch match;
  while (std::regex_search(begin, log.cend(), match, location)) {
    const std::size_t line = std::stoul(match[2].matched ? match[2].str() : match[3].str());
    result.append(begin, match[0].first);
    result += match[1].str();
    if (line >= 1 && line <= shader.origins.size()) {
      const SourceLine& origin = shader.origins[line - 1];
      result += origin.file + ":" + std::to_string(origin.line);
    } else {
      result += match[0].str().substr(match[1].length());
    }
    begin = match[0].second;
  }
  result.append(begin, log.cend());
  return result;
}

}  // namespace firn::gl

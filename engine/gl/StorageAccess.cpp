#include "gl/StorageAccess.h"

#include <algorithm>
#include <cctype>
#include <cstring>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <utility>

#include "Error.h"
#include "gl/Program.h"

namespace firn::gl {

namespace {

bool isIdentifierChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

std::string trimmed(const std::string& text) {
  const std::size_t first = text.find_first_not_of(" \t");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t") + 1 - first);
}

// The names of a list: its remarks in parentheses dropped, a final period too, split at commas.
std::vector<std::string> listedNames(const std::string& path, const std::string& list) {
  std::string bare;
  int depth = 0;
  for (const char c : list) {
    if (c == '(') ++depth;
    if (depth == 0) bare += c;
    if (c == ')' && depth > 0) --depth;
  }
  bare = trimmed(bare);
  if (!bare.empty() && bare.back() == '.') bare.pop_back();
  std::vector<std::string> names;
  std::istringstream items(bare);
  for (std::string item; std::getline(items, item, ',');) {
    const std::string name = trimmed(item);
    const bool identifier = !name.empty() && std::isalpha(static_cast<unsigned char>(name[0])) != 0 &&
                            std::all_of(name.begin(), name.end(), isIdentifierChar);
    if (!identifier) throw GLError(path + ": Reads:/Writes: names a block \"" + name + "\" (expected a block's name)");
    if (name != "nothing") names.push_back(name);
  }
  return names;
}

// GLSL `text` without its comments and (unless `keepBlocks`) the storage blocks' declarations (`buffer X { … };`).
std::string codeOnly(const std::string& text, bool keepBlocks) {
  std::string code;
  code.reserve(text.size());
  for (std::size_t i = 0; i < text.size();) {
    if (text.compare(i, 2, "//") == 0) {
      i = text.find('\n', i);
      if (i == std::string::npos) break;
    } else if (text.compare(i, 2, "/*") == 0) {
      const std::size_t end = text.find("*/", i + 2);
      code += ' ';
      i = end == std::string::npos ? text.size() : end + 2;
    } else if (!keepBlocks && text.compare(i, 6, "buffer") == 0 && (i == 0 || !isIdentifierChar(text[i - 1])) &&
               i + 6 < text.size() && !isIdentifierChar(text[i + 6])) {
      const std::size_t open = text.find('{', i), semicolon = text.find(';', i);
      if (open == std::string::npos || semicolon < open) {  // `buffer` as a word elsewhere: kept
        code += text[i++];
        continue;
      }
      const std::size_t close = text.find('}', open);
      i = close == std::string::npos ? text.size() : close + 1;
    } else {
      code += text[i++];
    }
  }
  return code;
}

// The identifiers the code of `text` can reach from main(): the bodies of the functions it calls, transitively, the
// macros they use, and what stands outside every function (declarations, shared arrays). A rough reading of GLSL,
// which takes every #ifdef's branches alike and an overloaded name's every body: it can only find more, not less.
std::set<std::string> reachableIdentifiers(const std::string& text) {
  const std::string code = codeOnly(text, false);
  std::map<std::string, std::set<std::string>> bodies;  // functions' and macros'
  std::set<std::string> roots = {"main"};
  std::set<std::string> statement;  // what is read outside the functions since the last `;`: a declaration's
  std::set<std::string> skipped;    // a struct's members: names, not code
  std::set<std::string>* current = &statement;  // where the identifiers read now belong
  std::string lastIdentifier, calledName;
  char lastSymbol = 0;
  int depth = 0, parentheses = 0;
  for (std::size_t i = 0; i < code.size();) {
    const char c = code[i];
    if (c == '#' && (i == 0 || code[i - 1] == '\n' || std::isspace(static_cast<unsigned char>(code[i - 1])))) {
      std::size_t end = i;
      do {  // a directive, with its continuation lines
        end = code.find('\n', end + 1);
      } while (end != std::string::npos && code[end - 1] == '\\');
      const std::string directive = code.substr(i, end == std::string::npos ? std::string::npos : end - i);
      std::istringstream words(directive);
      std::string hash, name;
      words >> hash >> name;
      std::set<std::string>& into = hash == "#define" ? bodies[name.substr(0, name.find('('))] : roots;
      for (std::string word; words >> word;) into.insert(word);  // split finely below, when read
      i = end == std::string::npos ? code.size() : end;
      continue;
    }
    if (isIdentifierChar(c) && !std::isdigit(static_cast<unsigned char>(c))) {
      std::size_t end = i;
      while (end < code.size() && isIdentifierChar(code[end])) ++end;
      lastIdentifier = code.substr(i, end - i);
      if (lastSymbol != '.') current->insert(lastIdentifier);  // a member or a swizzle, not a name of its own
      lastSymbol = 'a';
      i = end;
      continue;
    }
    // A function's name stands before the first parenthesis of its signature (not a macro's within it).
    if (c == '(' && depth == 0 && parentheses == 0 && lastSymbol == 'a') calledName = lastIdentifier;
    if (c == '(') ++parentheses;
    if (c == ')' && parentheses > 0) --parentheses;
    if (c == '{') {
      if (depth == 0) {
        current = lastSymbol == ')' ? &bodies[calledName] : &skipped;  // a function's body, or a struct's
        statement.clear();  // a function's signature is not code
      }
      ++depth;
    } else if (c == '}') {
      if (--depth == 0) current = &statement;
    } else if (c == ';' && depth == 0) {
      roots.insert(statement.begin(), statement.end());
      statement.clear();
    }
    if (!std::isspace(static_cast<unsigned char>(c))) lastSymbol = isIdentifierChar(c) ? 'a' : c;
    ++i;
  }
  // The words of a directive are split into identifiers, then everything main() reaches is visited.
  const auto identifiersOf = [](const std::set<std::string>& words) {
    std::set<std::string> identifiers;
    for (const std::string& word : words) {
      std::string name;
      for (const char c : word + " ") {
        if (isIdentifierChar(c)) {
          name += c;
        } else {
          if (!name.empty() && !std::isdigit(static_cast<unsigned char>(name[0]))) identifiers.insert(name);
          name.clear();
        }
      }
    }
    return identifiers;
  };
  std::set<std::string> reached;
  std::vector<std::string> pending;
  for (const std::string& name : identifiersOf(roots)) pending.push_back(name);
  while (!pending.empty()) {
    const std::string name = pending.back();
    pending.pop_back();
    if (!reached.insert(name).second) continue;
    const auto body = bodies.find(name);
    if (body == bodies.end()) continue;
    for (const std::string& next : identifiersOf(body->second)) pending.push_back(next);
  }
  return reached;
}

// Whether `code` declares the storage block `block` (`buffer <block>`).
bool declaresBlock(const std::string& code, const std::string& block) {
  for (std::size_t at = code.find(block); at != std::string::npos; at = code.find(block, at + 1)) {
    const std::size_t end = at + block.size();
    if ((end < code.size() && isIdentifierChar(code[end])) || (at > 0 && isIdentifierChar(code[at - 1]))) continue;
    std::size_t before = at;
    while (before > 0 && std::isspace(static_cast<unsigned char>(code[before - 1]))) --before;
    if (before >= 6 && code.compare(before - 6, 6, "buffer") == 0 &&
        (before == 6 || !isIdentifierChar(code[before - 7]))) {
      return true;
    }
  }
  return false;
}

// "FooBarBuffer" for "fooBar".
std::string blockName(const std::string& name) {
  return std::string(1, char(std::toupper(static_cast<unsigned char>(name[0])))) + name.substr(1) + "Buffer";
}

}  // namespace

std::optional<DeclaredAccess> declaredAccess(const std::string& path, const std::string& text) {
  std::optional<std::string> reads, writes;
  std::string* open = nullptr;  // the list whose last line ended with a comma
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.rfind("#version", 0) == 0 || trimmed(line).empty()) continue;
    if (line.rfind("//", 0) != 0) break;  // the first line of code: the header has ended
    const std::string comment = trimmed(line.substr(2));
    if (open != nullptr) {
      *open += " " + comment;
    } else {
      for (auto [kind, list] : {std::pair{"Reads:", &reads}, std::pair{"Writes:", &writes}}) {
        if (comment.rfind(kind, 0) != 0) continue;
        if (*list) throw GLError(path + ": its header has a second " + kind + " line");
        *list = comment.substr(std::strlen(kind));
        open = &**list;
      }
    }
    // A list goes on after a line that ends with a comma or inside a remark's parentheses.
    if (open != nullptr && (open->empty() || open->back() != ',') &&
        std::count(open->begin(), open->end(), '(') <= std::count(open->begin(), open->end(), ')')) {
      open = nullptr;
    }
  }
  if (!reads && !writes) return std::nullopt;
  if (!reads || !writes) throw GLError(path + ": its header has a " + (reads ? "Reads:" : "Writes:") +
                                       " line but no " + (reads ? "Writes:" : "Reads:") + " line");
  return DeclaredAccess{listedNames(path, *reads), listedNames(path, *writes)};
}

namespace {

// Binding `binding`'s bit; a program's bindings lie within the sets' 64 (GpuLayout.h keeps Firn's below 32).
BindingSet checkedBit(const std::string& path, GLuint binding) {
  if (binding >= 64) throw std::logic_error(path + ": storage binding " + std::to_string(binding) + " is beyond 63");
  return bindingBit(binding);
}

}  // namespace

StorageAccess undeclaredAccess(const std::string& path, const Program& program) {
  StorageAccess access;
  for (const GLuint binding : program.storageBindings()) access.reads |= checkedBit(path, binding);
  access.writes = access.reads;
  return access;
}

StorageAccess resolveAccess(const std::string& path, const DeclaredAccess& declared, const Program& program,
                            const std::string& text) {
  StorageAccess access;
  access.declared = true;
  const std::string code = codeOnly(text, true);
  const auto resolve = [&](const std::vector<std::string>& names, BindingSet& set) {
    for (const std::string& name : names) {
      // A block this build leaves out drops out; a name no source declares is a mistake, which would lose a barrier.
      if (!declaresBlock(code, blockName(name))) {
        throw std::logic_error(path + ": its header names " + name + ", but no block " + blockName(name) +
                               " is declared in its code");
      }
      const int binding = program.storageBlockBinding(blockName(name));
      if (binding >= 0) set |= checkedBit(path, GLuint(binding));
    }
  };
  resolve(declared.reads, access.reads);
  resolve(declared.writes, access.writes);
  const std::set<std::string> named = reachableIdentifiers(text);
  for (const auto& [member, binding] : program.storageMembers()) {
    if ((access.reads | access.writes) & checkedBit(path, binding) || named.count(member) == 0) continue;
    throw std::logic_error(path + " uses " + member + " (storage binding " + std::to_string(binding) +
                           "), whose block its header's Reads:/Writes: lines do not name");
  }
  return access;
}

}  // namespace firn::gl

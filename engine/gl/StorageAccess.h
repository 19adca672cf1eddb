#pragma once
// What a compute pass reads and writes of the shader storage blocks, by binding point, as its shader's header
// declares it. The header of each pass's file holds one line of each kind,
//
//   // Reads: positionMass, blockMap, bins (y: each bin's first), particleRanks.
//   // Writes: sortedParticles.
//
// naming blocks (`fooBar` is the block FooBarBuffer), each with an optional remark in parentheses; a list that ends
// its line with a comma, or inside a remark, goes on on the next comment line, and `nothing` is the empty list. The
// header is the file's comment lines before its first line of code (blank lines and #version aside). The barriers
// between passes follow from these declarations (gl/BufferBindings.h), and so does the count of bytes each pass moves.
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace firn::gl {

class Program;

// The names a header declares, as written.
struct DeclaredAccess {
  std::vector<std::string> reads;
  std::vector<std::string> writes;
};

// The declarations of a shader file's leading comment, or nothing where it has none (a pass that declares nothing
// is ordered by its caller's own barriers). Throws GLError naming `path` for a header that has one kind and not the
// other, or a name that is not an identifier.
std::optional<DeclaredAccess> declaredAccess(const std::string& path, const std::string& text);

// A set of storage binding points: bit b for binding b.
using BindingSet = std::uint64_t;
constexpr BindingSet bindingBit(unsigned binding) { return BindingSet(1) << binding; }

struct StorageAccess {
  BindingSet reads = 0;
  BindingSet writes = 0;
  bool declared = false;  // false: the pass declared nothing, and counts as reading and writing every block it has
};

// A pass that declares nothing: every block of `program` read and written.
StorageAccess undeclaredAccess(const std::string& path, const Program& program);

// The declarations resolved against a linked program, whose preprocessed source is `text`: the blocks it has (a build
// may leave some out). Throws std::logic_error naming `path` when the code names a member of a block its header does
// not name: a pass's declarations must be whole, or a barrier would be missing. The code is read as text, every
// #ifdef's branches alike (drivers report every declared block as used: Mesa's GL_REFERENCED_BY_COMPUTE_SHADER reads
// 0 for all), outside comments and the blocks' own declarations: what main() reaches through the functions it calls
// and the macros they use. A local variable named as a member (`slots`) reads as a use of it: name it otherwise. Blocks
// are declared without instance names (their members are named directly), as the check reads them.
StorageAccess resolveAccess(const std::string& path, const DeclaredAccess& declared, const Program& program,
                            const std::string& text);

}  // namespace firn::gl

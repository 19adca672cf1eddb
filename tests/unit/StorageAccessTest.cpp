// The declarations a compute shader's header makes of the storage blocks it reads and writes (gl/StorageAccess.h):
// the barriers between the step's passes follow from them, so a header that says too little, or something else than
// a list of names, must not pass as a declaration.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "Error.h"
#include "gl/ShaderLibrary.h"
#include "gl/StorageAccess.h"

namespace {

using firn::gl::declaredAccess;
using Names = std::vector<std::string>;

TEST(StorageAccess, HeaderListsNamesWithRemarksAcrossLines) {
  const std::string text =
      "#version 430 core\n"
      "// Sorts the particles.\n"
      "// Reads: positionMass, blockMap (the slots, and\n"
      "// whether they are new), bins (y: each bin's first),\n"
      "//   particleRanks.\n"
      "// Writes: sortedParticles (the indices).\n"
      "#include \"common/blocks.glsl\"\n"
      "// Reads: once the comment has ended, nothing is read from it.\n";
  const auto declared = declaredAccess("sim/bin_place.comp", text);
  ASSERT_TRUE(declared.has_value());
  EXPECT_EQ(declared->reads, (Names{"positionMass", "blockMap", "bins", "particleRanks"}));
  EXPECT_EQ(declared->writes, (Names{"sortedParticles"}));

  const auto none = declaredAccess("sim/count.comp", "#version 430 core\n// Reads: nothing.\n// Writes: blockTable\n");
  ASSERT_TRUE(none.has_value());
  EXPECT_TRUE(none->reads.empty());
  EXPECT_EQ(none->writes, (Names{"blockTable"}));
}

// The header runs to the first line of code: a blank line between its paragraphs does not end it.
TEST(StorageAccess, BlankLinesDoNotEndTheHeader) {
  const auto declared =
      declaredAccess("sim/a.comp", "#version 430 core\n// A pass.\n\n// Reads: xs.\n// Writes: ys.\n");
  ASSERT_TRUE(declared.has_value());
  EXPECT_EQ(declared->writes, (Names{"ys"}));
}

// Every pass of the step declares what it reads and writes: the step's barriers follow from nothing else (a pass that
// declares nothing would count as touching every block, which no test would notice).
TEST(StorageAccess, EveryPassOfTheStepDeclares) {
  std::size_t passes = 0;
  for (const auto& [path, text] : firn::gl::embeddedShaderFiles()) {
    if (path.rfind("sim/", 0) != 0 || path.size() < 5 || path.compare(path.size() - 5, 5, ".comp") != 0) continue;
    ++passes;
    EXPECT_TRUE(declaredAccess(path, text).has_value()) << path;
  }
  EXPECT_GE(passes, 34u);
}

TEST(StorageAccess, AHeaderWithoutDeclarationsDeclaresNothing) {
  EXPECT_FALSE(declaredAccess("surface/scan.comp", "#version 430 core\n// It reads the values.\nvoid main() {}\n"));
}

// Prose where names belong, or one list without the other, is an error naming the file: it would otherwise declare
// less than the pass does.
TEST(StorageAccess, ProseOrAMissingListIsAnErrorNamingTheFile) {
  const auto expectError = [](const std::string& text, const std::string& expected) {
    try {
      (void)declaredAccess("sim/p2g.comp", text);
      ADD_FAILURE() << "accepted: " << text;
    } catch (const firn::GLError& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find("sim/p2g.comp"), std::string::npos) << message;
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  };
  expectError("#version 430 core\n// Reads: grid sums, the block table.\n// Writes: gridMomentumMass\n",
              "\"grid sums\"");
  expectError("#version 430 core\n// Reads: positionMass\n", "no Writes: line");
  expectError("#version 430 core\n// Writes: positionMass\n", "no Reads: line");
  expectError("#version 430 core\n// Reads: positionMass[].xyz\n// Writes: nothing\n", "\"positionMass[].xyz\"");
  expectError("#version 430 core\n// Reads: bins\n// Writes: nothing\n// Reads: positionMass\n", "a second Reads:");
}

}  // namespace

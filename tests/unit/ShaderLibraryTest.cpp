#include <gtest/gtest.h>

#include "Error.h"
#include "gl/ShaderLibrary.h"

namespace {

using firn::gl::ShaderLibrary;

ShaderLibrary exampleLibrary() {
  return ShaderLibrary({
      {"main.comp", "#version 430 core\n#include \"common/a.glsl\"\nvoid main() {}\n"},
      {"common/a.glsl", "#include \"common/b.glsl\"\nfloat a() { return b(); }\n"},
      {"common/b.glsl", "float b() { return 1.0; }\n"},
      {"twice.comp", "#version 430 core\n#include \"common/b.glsl\"\n#include \"common/b.glsl\"\n"},
      {"broken.comp", "#version 430 core\n#include \"common/missing.glsl\"\n"},
      {"noversion.comp", "void main() {}\n"},
  });
}

TEST(ShaderLibrary, DefinesAndExtensionsFollowVersion) {
  firn::gl::ShaderOptions options;
  options.defines = {{"FIRN_KERNEL_CUBIC", "1"}};
  options.extensions = {"GL_NV_shader_atomic_float"};
  const auto shader = exampleLibrary().preprocess("main.comp", options);
  EXPECT_EQ(shader.text.rfind("#version 430 core\n#extension GL_NV_shader_atomic_float : require\n"
                              "#define FIRN_KERNEL_CUBIC 1\n", 0), 0u)
      << shader.text;
}

TEST(ShaderLibrary, IncludesEachFileOnceWithLineDirectives) {
  const auto shader = exampleLibrary().preprocess("main.comp", {});
  ASSERT_EQ(shader.sourceNames.size(), 4u);  // <injected>, main.comp, common/a.glsl, common/b.glsl
  EXPECT_EQ(shader.sourceNames[1], "main.comp");
  EXPECT_EQ(shader.sourceNames[3], "common/b.glsl");
  EXPECT_NE(shader.text.find("#line 1 3\nfloat b()"), std::string::npos) << shader.text;
  // Back in a.glsl after its include on line 1: line 2 of source 2.
  EXPECT_NE(shader.text.find("#line 2 2\nfloat a()"), std::string::npos) << shader.text;
  // Back in main.comp after line 2's include.
  EXPECT_NE(shader.text.find("#line 3 1\nvoid main()"), std::string::npos) << shader.text;

  const auto twice = exampleLibrary().preprocess("twice.comp", {});
  std::size_t definitions = 0;
  for (std::size_t at = twice.text.find("float b()"); at != std::string::npos; at = twice.text.find("float b()", at + 1)) {
    ++definitions;
  }
  EXPECT_EQ(definitions, 1u);
}

TEST(ShaderLibrary, MissingIncludeNamesFileAndLine) {
  try {
    exampleLibrary().preprocess("broken.comp", {});
    FAIL() << "expected GLError";
  } catch (const firn::GLError& error) {
    EXPECT_NE(std::string(error.what()).find("broken.comp:2: included file not found: common/missing.glsl"),
              std::string::npos)
        << error.what();
  }
  EXPECT_THROW(exampleLibrary().preprocess("noversion.comp", {}), firn::GLError);
  EXPECT_THROW(exampleLibrary().preprocess("absent.comp", {}), firn::GLError);
}

// Driver logs name sources by number: Mesa writes "3:12(5): error", NVIDIA "3(12) : error".
TEST(ShaderLibrary, TranslatesDriverLogLocations) {
  const auto shader = exampleLibrary().preprocess("main.comp", {});
  EXPECT_EQ(ShaderLibrary::translateLog("3:12(5): error: x undeclared\n2:4(1): warning: y\n", shader),
            "common/b.glsl:12: error: x undeclared\ncommon/a.glsl:4: warning: y\n");
  EXPECT_EQ(ShaderLibrary::translateLog("1(7) : error C1008: undefined variable", shader),
            "main.comp:7 : error C1008: undefined variable");
}

// Every shipped shader preprocesses: includes resolve and each pass starts with #version.
TEST(ShaderLibrary, EmbeddedPassesPreprocess) {
  const ShaderLibrary library;
  for (const char* pass : {"sim/prepare_grid.comp", "sim/clear_grid.comp", "sim/p2g.comp", "sim/update_grid.comp",
                           "sim/g2p.comp", "sim/compute_volumes.comp"}) {
    EXPECT_NO_THROW(library.preprocess(pass, {})) << pass;
  }
}

}  // namespace

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

TEST(ShaderLibrary, IncludesEachFileOnceAndMapsLinesBack) {
  const auto shader = exampleLibrary().preprocess("main.comp", {});
  EXPECT_EQ(shader.text,
            "#version 430 core\nfloat b() { return 1.0; }\nfloat a() { return b(); }\nvoid main() {}\n");
  ASSERT_EQ(shader.origins.size(), 4u);
  EXPECT_EQ(shader.origins[1].file, "common/b.glsl");
  EXPECT_EQ(shader.origins[1].line, 1);
  EXPECT_EQ(shader.origins[2].file, "common/a.glsl");
  EXPECT_EQ(shader.origins[2].line, 2);
  EXPECT_EQ(shader.origins[3].file, "main.comp");
  EXPECT_EQ(shader.origins[3].line, 3);

  const auto twice = exampleLibrary().preprocess("twice.comp", {});
  EXPECT_EQ(twice.text, "#version 430 core\nfloat b() { return 1.0; }\n");
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

// Driver logs give a line of the expanded text: Mesa writes "0:3(5): error", NVIDIA "0(3) : error".
TEST(ShaderLibrary, TranslatesDriverLogLocations) {
  firn::gl::ShaderOptions options;
  options.defines = {{"A", "1"}};  // shifts every line by one
  const auto shader = exampleLibrary().preprocess("main.comp", options);
  EXPECT_EQ(ShaderLibrary::translateLog("0:3(5): error: x undeclared\n0:4(1): warning: y\n", shader),
            "common/b.glsl:1: error: x undeclared\ncommon/a.glsl:2: warning: y\n");
  EXPECT_EQ(ShaderLibrary::translateLog("0(5) : error C1008: undefined variable", shader),
            "main.comp:3 : error C1008: undefined variable");
  EXPECT_EQ(ShaderLibrary::translateLog("0:2(1): error: bad define", shader), "<injected>:1: error: bad define");
}

// Every shipped shader preprocesses: includes resolve and each pass starts with #version.
TEST(ShaderLibrary, EmbeddedPassesPreprocess) {
  const ShaderLibrary library;
  for (const char* pass : {"sim/prepare_blocks.comp", "sim/release_blocks.comp", "sim/mark_blocks.comp",
                           "sim/count_blocks.comp", "sim/bin_count.comp", "sim/bin_scan.comp", "sim/block_offsets.comp",
                           "sim/bin_place.comp", "sim/order_tiles.comp", "sim/p2g.comp", "sim/update_grid.comp",
                           "sim/g2p.comp", "sim/compute_volumes.comp"}) {
    EXPECT_NO_THROW(library.preprocess(pass, {})) << pass;
  }
}

}  // namespace

// Shader failures are loud and precise: the driver's log with file:line of the original source.
#include <gtest/gtest.h>

#include <string>
#include <utility>
#include <vector>

#include "Error.h"
#include "GlTest.h"
#include "gl/Program.h"
#include "gpu/GpuLayout.h"

namespace {

TEST(ShaderCompile, ErrorNamesIncludedFileAndLine) {
  firn::test::glContext();
  firn::gl::ShaderLibrary library({
      {"test/main.comp", "#version 430 core\nlayout(local_size_x = 1) in;\n#include \"test/helper.glsl\"\n"
                         "void main() { helper(); }\n"},
      {"test/helper.glsl", "// a helper with a typo on line 3\nvoid helper() {\n  undeclaredVariable = 1.0;\n}\n"},
  });
  try {
    firn::gl::Program::compute(library, "test/main.comp", {});
    FAIL() << "expected GLError";
  } catch (const firn::GLError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("compiling test/main.comp failed"), std::string::npos) << message;
    EXPECT_NE(message.find("test/helper.glsl:3"), std::string::npos) << message;
    EXPECT_NE(message.find("undeclaredVariable"), std::string::npos) << message;
  }
}

TEST(ShaderCompile, EveryPassCompilesForEveryConfiguration) {
  firn::test::glContext();
  const firn::gl::ShaderLibrary library;
  for (const char* kernel : {"FIRN_KERNEL_QUADRATIC", "FIRN_KERNEL_CUBIC"}) {
    for (const char* transfer : {"FIRN_TRANSFER_APIC", "FIRN_TRANSFER_PIC_FLIP"}) {
      firn::gl::ShaderOptions options;
      options.defines = {{kernel, "1"}, {transfer, "1"}, {"FIRN_HAS_COLLIDERS", "1"}, {"FIRN_WALL_CELLS", "2"}};
      for (const char* pass : {"sim/prepare_blocks.comp", "sim/release_blocks.comp", "sim/mark_blocks.comp",
                               "sim/count_blocks.comp", "sim/bin_count.comp", "sim/bin_scan.comp",
                               "sim/block_offsets.comp", "sim/bin_place.comp", "sim/order_tiles.comp", "sim/p2g.comp",
                               "sim/p2g_block.comp", "sim/update_grid.comp", "sim/compute_volumes.comp"}) {
        EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, options)) << pass << " " << kernel << " " << transfer;
      }
      // G2P holds the material models: each alone (water without F), and all of them together.
      using Defines = std::vector<std::pair<std::string, std::string>>;
      const Defines withF = {{"FIRN_HAS_DEFORMATION_GRADIENT", "1"}};
      for (const Defines& materials :
           {Defines{{"FIRN_MATERIAL_SNOW", "1"}}, Defines{{"FIRN_MATERIAL_FIXED_COROTATED", "1"}},
            Defines{{"FIRN_MATERIAL_NEO_HOOKEAN", "1"}}, Defines{{"FIRN_MATERIAL_DRUCKER_PRAGER", "1"}},
            Defines{{"FIRN_MATERIAL_SNOW", "1"}, {"FIRN_MATERIAL_FIXED_COROTATED", "1"}, {"FIRN_MATERIAL_NEO_HOOKEAN", "1"},
                    {"FIRN_MATERIAL_WATER", "1"}, {"FIRN_MATERIAL_DRUCKER_PRAGER", "1"}}}) {
        firn::gl::ShaderOptions g2p = options;
        g2p.defines.insert(g2p.defines.end(), materials.begin(), materials.end());
        g2p.defines.insert(g2p.defines.end(), withF.begin(), withF.end());
        EXPECT_NO_THROW(firn::gl::Program::compute(library, "sim/g2p.comp", g2p))
            << materials.front().first << " (" << materials.size() << " models) " << kernel << " " << transfer;
      }
      firn::gl::ShaderOptions waterOnly = options;
      waterOnly.defines.emplace_back("FIRN_MATERIAL_WATER", "1");
      EXPECT_NO_THROW(firn::gl::Program::compute(library, "sim/g2p.comp", waterOnly)) << "water alone, no F";
      // Semi-implicit scenes: the models with a Hessian, adaptive steps, and the test build of the product. The
      // product with APIC's buffers declares 16 storage blocks, llvmpipe's limit (docs/platform.md): one more fails
      // here.
      firn::gl::ShaderOptions semiImplicit = options;
      semiImplicit.defines.insert(semiImplicit.defines.end(),
                                  {{"FIRN_SEMI_IMPLICIT", "1"}, {"FIRN_ADAPTIVE_DT", "1"}, {"FIRN_MATERIAL_SNOW", "1"},
                                   {"FIRN_MATERIAL_FIXED_COROTATED", "1"}, {"FIRN_MATERIAL_NEO_HOOKEAN", "1"},
                                   {"FIRN_HAS_DEFORMATION_GRADIENT", "1"}});
      firn::gl::ShaderOptions forceDifference = semiImplicit;
      forceDifference.defines.emplace_back("FIRN_SOLVER_FORCE_DIFFERENCE", "1");
      EXPECT_NO_THROW(firn::gl::Program::compute(library, "sim/solver_product.comp", forceDifference))
          << "force difference " << kernel << " " << transfer;
      for (const char* pass : {"sim/update_grid.comp", "sim/g2p.comp", "sim/solver_prepare.comp", "sim/solver_begin.comp",
                               "sim/solver_product.comp", "sim/solver_residual.comp", "sim/solver_apply.comp",
                               "sim/solver_step.comp", "sim/solver_reduce.comp", "sim/solver_finish.comp",
                               "sim/solver_solution.comp"}) {
        EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, semiImplicit))
            << pass << " semi-implicit " << kernel << " " << transfer;
      }
      // The rigid bodies' passes and those that push them, in the semi-implicit step, whose solve takes the bodies'
      // velocities as unknowns (docs/algorithm.md, eq. 39a).
      firn::gl::ShaderOptions withBodies = semiImplicit;
      withBodies.defines.insert(withBodies.defines.end(), {{"FIRN_HAS_COLLIDERS", "1"}, {"FIRN_HAS_COLLIDER_FIELDS", "1"},
                                                           {"FIRN_HAS_MESH_SHAPES", "1"}, {"FIRN_HAS_RIGID_BODIES", "1"}});
      for (const char* pass : {"sim/update_grid.comp", "sim/predict_bodies.comp", "sim/solver_residual.comp",
                               "sim/solver_apply.comp", "sim/solver_step.comp", "sim/solver_reduce.comp",
                               "sim/solver_bodies_residual.comp", "sim/solver_bodies_apply.comp",
                               "sim/solver_bodies_step.comp", "sim/solver_bodies_finish.comp", "sim/solver_finish.comp",
                               "sim/meet_bodies.comp", "sim/g2p.comp", "sim/integrate_bodies.comp"}) {
        EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, withBodies))
            << pass << " semi-implicit with rigid bodies " << kernel << " " << transfer;
      }
      // The explicit step's, with its coupled solve of the bodies and the nodes they hold (docs/algorithm.md, eq. 39).
      firn::gl::ShaderOptions explicitBodies = options;
      explicitBodies.defines.insert(explicitBodies.defines.end(),
                                    {{"FIRN_HAS_COLLIDERS", "1"}, {"FIRN_HAS_COLLIDER_FIELDS", "1"},
                                     {"FIRN_HAS_MESH_SHAPES", "1"}, {"FIRN_HAS_RIGID_BODIES", "1"}, {"FIRN_ADAPTIVE_DT", "1"}});
      for (const char* pass : {"sim/update_grid.comp", "sim/predict_bodies.comp", "sim/solve_coupling.comp",
                               "sim/meet_bodies.comp", "sim/couple_nodes.comp", "sim/list_mirror_blocks.comp",
                               "sim/list_mirrored.comp", "sim/claim_image_blocks.comp", "sim/mirror_stress.comp",
                               "sim/g2p.comp", "sim/integrate_bodies.comp"}) {
        EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, explicitBodies))
            << pass << " explicit with rigid bodies " << kernel << " " << transfer;
      }
      // The product in both shapes, the first product's too (its block shape holds the most shared memory).
      for (const char* groupSize : {"", "64", "256"}) {
        for (const bool first : {false, true}) {
          firn::gl::ShaderOptions product = semiImplicit;
          if (first) product.defines.emplace_back("FIRN_SOLVER_FIRST_PRODUCT", "1");
          if (*groupSize != '\0') product.defines.emplace_back("FIRN_P2G_BLOCK_GROUP_SIZE", groupSize);
          const char* pass = *groupSize == '\0' ? "sim/solver_product.comp" : "sim/solver_product_block.comp";
          EXPECT_NO_THROW(firn::gl::Program::compute(library, pass, product))
              << pass << " " << groupSize << (first ? " first product " : " ") << kernel << " " << transfer;
        }
      }
    }
  }
}

}  // namespace

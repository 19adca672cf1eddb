// The barriers between compute passes follow from what each pass's header declares it reads and writes
// (gl/StorageAccess.h, gl/BufferBindings.h): a pass waits where it reads what an earlier pass wrote since the last
// barrier, or writes what one read or wrote since; passes that share nothing run without one; an indirect dispatch
// waits for the commands an earlier pass wrote. A program that uses a block its header does not name is refused.
#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "GlTest.h"
#include "gl/Buffer.h"
#include "gl/BufferBindings.h"
#include "gl/ComputePass.h"
#include "gl/PassTimer.h"
#include "gl/ShaderLibrary.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

using firn::gl::Buffer;
using firn::gl::BufferBindings;
using firn::gl::ComputePass;

constexpr unsigned kValues = 256;

// Three blocks of kValues uints (xs, ys, zs) and a dispatch record (commands), and passes over them.
const char* const kBlocks =
    "layout(local_size_x = 64) in;\n"
    "layout(std430, binding = 0) buffer XsBuffer { uint xs[]; };\n"
    "layout(std430, binding = 1) buffer YsBuffer { uint ys[]; };\n"
    "layout(std430, binding = 2) buffer ZsBuffer { uint zs[]; };\n"
    "layout(std430, binding = 3) buffer CommandsBuffer { uvec4 groups; };\n";

firn::gl::ShaderLibrary passLibrary() {
  const auto pass = [](const std::string& header, const std::string& body) {
    return "#version 430 core\n" + header + kBlocks + "void main() { uint i = gl_GlobalInvocationID.x; " + body +
           " }\n";
  };
  return firn::gl::ShaderLibrary({
      {"write_x.comp", pass("// Reads: nothing.\n// Writes: xs.\n", "xs[i] = i + 1u;")},
      {"write_y.comp", pass("// Reads: nothing.\n// Writes: ys (twice x's value).\n", "ys[i] = 2u * (i + 1u);")},
      {"sum_into_z.comp", pass("// Reads: xs, ys.\n// Writes: zs.\n", "zs[i] = xs[i] + ys[i];")},
      {"size_dispatch.comp",
       pass("// Reads: nothing.\n// Writes: commands.\n", "if (i == 0u) groups = uvec4(4u, 1u, 1u, 0u);")},
      {"undeclared_z.comp", pass("// Adds one to z.\n", "zs[i] += 1u;")},
      {"half_declared.comp", pass("// Reads: xs.\n// Writes: nothing.\n", "ys[i] = xs[i];")},
      {"misspelled.comp", pass("// Reads: xs.\n// Writes: ys, zz.\n", "ys[i] = xs[i];")},
      {"helper_unused.comp",
       "#version 430 core\n// Reads: xs.\n// Writes: zs.\n" + std::string(kBlocks) +
           "uint unused(uint i) { return ys[i]; }\n"
           "uint twice(uint i) { return 2u * xs[i]; }\n"
           "void main() { uint i = gl_GlobalInvocationID.x; zs[i] = twice(i); }\n"},
      {"helper_used.comp",
       "#version 430 core\n// Reads: xs.\n// Writes: zs.\n" + std::string(kBlocks) +
           "#define GROUPS groups.x\n"
           "uint count() { return GROUPS; }\n"
           "void main() { uint i = gl_GlobalInvocationID.x; zs[i] = xs[i] + count(); }\n"},
  });
}

struct Passes {
  firn::gl::ShaderLibrary library = passLibrary();
  ComputePass writeX{library, "write_x.comp", {}};
  ComputePass writeY{library, "write_y.comp", {}};
  ComputePass sumIntoZ{library, "sum_into_z.comp", {}};
  ComputePass sizeDispatch{library, "size_dispatch.comp", {}};
  ComputePass undeclaredZ{library, "undeclared_z.comp", {}};
};

TEST(PassOrder, BarriersFollowFromTheDeclarations) {
  firn::test::glContext();
  const Passes passes;
  Buffer xs(kValues * 4), ys(kValues * 4), zs(kValues * 4), commands(16);
  BufferBindings buffers;
  buffers.storage(0, xs);
  buffers.storage(1, ys);
  buffers.storage(2, zs);
  buffers.storage(3, commands);
  firn::gl::PassTimer untimed;
  std::vector<BufferBindings::PassRecord> record;
  buffers.recordPasses(&record);

  passes.writeX.runOver(kValues, 65535, buffers, untimed);
  passes.writeY.runOver(kValues, 65535, buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 0u) << "x and y share nothing";
  passes.sumIntoZ.runOver(kValues, 65535, buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 1u) << "z's sum reads x and y, written since no barrier";
  passes.sizeDispatch.runOnce(buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 1u) << "the commands share nothing with the sum";
  // Reads the commands written since the last barrier (a command barrier) and writes z, which the sum wrote (a
  // storage barrier): one glMemoryBarrier with both bits.
  passes.sumIntoZ.runIndirect(commands, 0, buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 2u);
  passes.writeX.runOver(kValues, 65535, buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 3u) << "x is written after the sum read it";
  // A pass that declares nothing counts as reading and writing every block it has: it waits for every pending write.
  passes.undeclaredZ.runOver(kValues, 65535, buffers, untimed);
  EXPECT_EQ(buffers.barriers(), 4u);
  buffers.completeWrites();
  EXPECT_EQ(buffers.barriers(), 5u) << "a pass that declares nothing may have written any of its blocks";
  buffers.completeWrites();
  EXPECT_EQ(buffers.barriers(), 5u) << "nothing was written since";
  buffers.recordPasses(nullptr);

  const std::vector<std::uint32_t> z = zs.read<std::uint32_t>(kValues);
  for (unsigned i = 0; i < kValues; ++i) EXPECT_EQ(z[i], 3u * (i + 1u) + 1u) << i;
  ASSERT_EQ(record.size(), 7u);
  EXPECT_EQ(record[2].phase, "sum_into_z.comp");
  EXPECT_EQ(record[2].access.reads, firn::gl::bindingBit(0) | firn::gl::bindingBit(1));
  EXPECT_EQ(record[2].access.writes, firn::gl::bindingBit(2));
  EXPECT_FALSE(record[6].access.declared);
}

// A block is used where main() reaches it, through the functions it calls and the macros they use: commands here, by
// way of count() and GROUPS; not ys, which only a function main() never calls names. A header that names a block no
// code declares, or leaves out one the code uses, is refused with the file, the name and the binding.
TEST(PassOrder, AProgramUsingABlockItsHeaderDoesNotNameIsRefused) {
  firn::test::glContext();
  const firn::gl::ShaderLibrary library = passLibrary();
  EXPECT_NO_THROW(ComputePass(library, "helper_unused.comp", {}));
  for (const auto& [file, expected] :
       {std::pair{"misspelled.comp", "misspelled.comp: its header names zz, but no block ZzBuffer"},
        std::pair{"helper_used.comp", "helper_used.comp uses groups (storage binding 3)"},
        std::pair{"half_declared.comp", "half_declared.comp uses ys (storage binding 1)"}}) {
    try {
      const ComputePass pass(library, file, {});
      ADD_FAILURE() << file << " was built";
    } catch (const std::logic_error& error) {
      const std::string message = error.what();
      EXPECT_NE(message.find(expected), std::string::npos) << message;
    }
  }
}

// What one step of the built-in scene (APIC, cubic, explicit, P2G by tiles) moves, as its passes' declarations count
// it (Simulation::stepRecordingTraffic): the sort reads each position three times and the ranks once (3 × 16 + 4 B),
// P2G x, v, τ, C and the sorted index (16 + 16 + 48 + 48 + 4 B), G2P x, v, F, the plastic state and the index (16 + 16
// + 48 + 16 + 4 B); the sort writes the ranks and the sorted indices (4 + 4 B) and G2P the whole 192 B state. Each of
// its 12 passes but order_tiles (which shares nothing with bin_place before it) waits for the one before it, and
// the step ends with one barrier for what reads the particles next: 11 barriers, as many as were placed by hand.
TEST(PassOrder, AStepMovesWhatItsPassesDeclare) {
  const firn::Scene scene = firn::defaultScene();
  firn::SimulationOptions tiles;
  tiles.transferShapes = "tiles";
  firn::Simulation simulation(scene, firn::sampleBodies(scene), firn::test::glContext().info(), tiles);
  simulation.step(scene.time.dtS);
  const firn::Simulation::StepTraffic traffic = simulation.stepRecordingTraffic(scene.time.dtS);
  std::size_t read = 0, written = 0;
  for (const firn::Simulation::PassTraffic& dispatch : traffic.dispatches) {
    read += dispatch.readBytesPerParticle;
    written += dispatch.writtenBytesPerParticle;
  }
  EXPECT_EQ(simulation.particleStateBytes(), 192u);
  EXPECT_EQ(read, 3u * 16 + 4 + 132 + 100);
  EXPECT_EQ(written, 4u + 4 + 192);
  EXPECT_EQ(traffic.dispatches.size(), 12u);
  EXPECT_EQ(traffic.barriers, 11u);
}

}  // namespace

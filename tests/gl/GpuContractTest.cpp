// The GPU contract (shaders/common/gpu_contract.h) holds on both sides: every member of every shared struct
// sits where the driver says the shaders read it, every buffer is bound where the host binds it, and the
// particle passes run in groups of the size the host dispatches for. The member lists are the contract's own
// X-macros, so a member added there is checked here without touching this test.
#include <gtest/gtest.h>

#include <cstddef>
#include <string>
#include <vector>

#include "GlTest.h"
#include "gl/Program.h"
#include "gpu/GpuLayout.h"
#include "surface/SurfaceLayout.h"

namespace {

using namespace firn::gpu;

struct Member {
  std::string name;
  std::size_t offsetBytes;
  bool matrix = false;  // read through its first column: a matrix has no .x
};

// The members of struct S, named as GLSL names them, with their C++ offsets.
#define FIRN_LIST_MEMBER(type, name) Member{#name, offsetof(S, name), std::string(#type).rfind("mat", 0) == 0},
#define FIRN_LIST_ARRAY(type, name, count) Member{#name "[0]", offsetof(S, name)},
#define FIRN_MEMBER_LIST(Struct, list)                \
  [] {                                                \
    using S = Struct;                                 \
    return std::vector<Member>{list(FIRN_LIST_MEMBER, FIRN_LIST_ARRAY)}; \
  }()

// Every shared struct: the common file that declares its block (after common/bindings.glsl), where GLSL finds
// it (a prefix before the member names), its members with their C++ offsets, and its offset within the block.
struct SharedStruct {
  std::string include;
  GLenum interface;  // GL_UNIFORM or GL_BUFFER_VARIABLE
  std::string prefix;
  std::vector<Member> members;
  std::size_t baseBytes = 0;
};

std::vector<SharedStruct> sharedStructs() {
  return {
      {"common/bindings.glsl", GL_UNIFORM, "", FIRN_MEMBER_LIST(StepUniforms, FIRN_STEP_UNIFORMS)},
      {"common/bindings.glsl", GL_BUFFER_VARIABLE, "materials[0].",
       FIRN_MEMBER_LIST(MaterialParams, FIRN_MATERIAL_PARAMS)},
      {"common/particles.glsl", GL_BUFFER_VARIABLE, "plasticState[0].",
       FIRN_MEMBER_LIST(ParticlePlasticState, FIRN_PARTICLE_PLASTIC_STATE)},
      {"common/watchdog.glsl", GL_BUFFER_VARIABLE, "", FIRN_MEMBER_LIST(WatchdogStatus, FIRN_WATCHDOG_STATUS)},
      // The energy ledger follows the watchdog's status, and the objects' loads follow the ledger.
      {"common/watchdog.glsl", GL_BUFFER_VARIABLE, "", FIRN_MEMBER_LIST(EnergyLedger, FIRN_ENERGY_LEDGER),
       sizeof(WatchdogStatus)},
      {"common/watchdog.glsl", GL_BUFFER_VARIABLE, "objectLoads[0].", FIRN_MEMBER_LIST(ObjectLoad, FIRN_OBJECT_LOAD),
       sizeof(WatchdogStatus) + sizeof(EnergyLedger)},
      {"common/colliders.glsl", GL_BUFFER_VARIABLE, "colliders[0].",
       FIRN_MEMBER_LIST(ColliderParams, FIRN_COLLIDER_PARAMS)},
      {"common/blocks.glsl", GL_BUFFER_VARIABLE, "", FIRN_MEMBER_LIST(BlockTableHeader, FIRN_BLOCK_TABLE_HEADER)},
      // The slots follow the block table's header.
      {"common/blocks.glsl", GL_BUFFER_VARIABLE, "slots[0].", FIRN_MEMBER_LIST(BlockSlot, FIRN_BLOCK_SLOT),
       sizeof(BlockTableHeader)},
      // The surface reconstruction's (shaders/surface/surface_contract.h).
      {"surface/surface_common.glsl", GL_UNIFORM, "", FIRN_MEMBER_LIST(SurfaceUniforms, FIRN_SURFACE_UNIFORMS)},
      {"surface/header.glsl", GL_BUFFER_VARIABLE, "", FIRN_MEMBER_LIST(SurfaceHeader, FIRN_SURFACE_HEADER)},
      {"surface/vertices.glsl", GL_BUFFER_VARIABLE, "vertices[0].", FIRN_MEMBER_LIST(SurfaceVertex, FIRN_SURFACE_VERTEX)},
      {"surface/node_sums.glsl", GL_BUFFER_VARIABLE, "nodeSums[0].",
       FIRN_MEMBER_LIST(SurfaceNodeSums, FIRN_SURFACE_NODE_SUMS)},
      // The semi-implicit solve's (common/solver.glsl).
      {"common/solver.glsl", GL_BUFFER_VARIABLE, "solverNodes[0].", FIRN_MEMBER_LIST(SolverNode, FIRN_SOLVER_NODE)},
      {"common/solver.glsl", GL_BUFFER_VARIABLE, "solverPreconditioners[0].",
       FIRN_MEMBER_LIST(SolverPreconditioner, FIRN_SOLVER_PRECONDITIONER)},
      {"common/material_hessians.glsl", GL_BUFFER_VARIABLE, "solverParticles[0].",
       FIRN_MEMBER_LIST(SolverParticle, FIRN_SOLVER_PARTICLE)},
      {"common/solver_reduction.glsl", GL_BUFFER_VARIABLE, "", FIRN_MEMBER_LIST(SolverStatus, FIRN_SOLVER_STATUS)},
      // The rigid bodies' records (common/body_blocks.glsl): the contact slots, then a record per body.
      {"common/body_blocks.glsl", GL_BUFFER_VARIABLE, "bodyContacts[0].",
       FIRN_MEMBER_LIST(BodyContact, FIRN_BODY_CONTACT)},
      {"common/body_blocks.glsl", GL_BUFFER_VARIABLE, "bodyRecords[0].",
       FIRN_MEMBER_LIST(BodyRecord, FIRN_BODY_RECORD), CONTACT_SLOTS * sizeof(BodyContact)},
  };
}

// A compute shader that declares the buffers the way the passes do (through the same common files: `include`
// after common/bindings.glsl) and reads `reads` (GLSL expressions), so that the driver reports them: it reports
// only what a shader uses, and Mesa 22 also leaves out some members of shaders that declare many blocks, so each
// struct gets a probe of its own.
firn::gl::Program probe(const std::string& include, const std::vector<std::string>& reads) {
  firn::test::glContext();
  std::string body;
  for (const std::string& read : reads) body += "  sum += float(" + read + ".x);\n";  // .x of a scalar too
  firn::gl::ShaderLibrary library;
  library.add("test/contract_probe.comp", "#version 430 core\n#include \"common/bindings.glsl\"\n#include \"" + include +
                                              "\"\nlayout(local_size_x = 1) in;\nvoid main() {\n  float sum = 0.0;\n" +
                                              body + "  positionMass[0] = vec4(sum);\n}\n");
  firn::gl::ShaderOptions options;
  options.defines = {{"FIRN_KERNEL_QUADRATIC", "1"}, {"FIRN_TRANSFER_APIC", "1"},
                     {"FIRN_HAS_DEFORMATION_GRADIENT", "1"}, {"FIRN_HAS_COLLIDERS", "1"},
                     {"FIRN_HAS_RIGID_BODIES", "1"}, {"FIRN_WALL_CELLS", "2"}};
  return firn::gl::Program::compute(library, "test/contract_probe.comp", options);
}

// GL_OFFSET, GL_ARRAY_STRIDE, GL_MATRIX_STRIDE and GL_TOP_LEVEL_ARRAY_STRIDE (the latter for buffer variables
// only) of `name`, or nothing if the driver does not know it.
std::vector<GLint> properties(const firn::gl::Program& program, GLenum interface, const std::string& name) {
  const GLuint index = glGetProgramResourceIndex(program.id(), interface, name.c_str());
  if (index == GL_INVALID_INDEX) return {};
  std::vector<GLenum> queries = {GL_OFFSET, GL_ARRAY_STRIDE, GL_MATRIX_STRIDE};
  if (interface == GL_BUFFER_VARIABLE) queries.push_back(GL_TOP_LEVEL_ARRAY_STRIDE);
  std::vector<GLint> values(queries.size(), -1);
  glGetProgramResourceiv(program.id(), interface, index, GLsizei(queries.size()), queries.data(), GLsizei(values.size()),
                         nullptr, values.data());
  return values;
}

GLint blockProperty(const firn::gl::Program& program, GLenum interface, const std::string& block, GLenum property) {
  const GLuint index = glGetProgramResourceIndex(program.id(), interface, block.c_str());
  if (index == GL_INVALID_INDEX) return -1;
  GLint value = -1;
  glGetProgramResourceiv(program.id(), interface, index, 1, &property, 1, nullptr, &value);
  return value;
}

// Exact: a layout either agrees byte for byte or the host writes where the shaders do not read.
TEST(GpuContract, StructMembersSitAtTheDriversOffsets) {
  for (const SharedStruct& shared : sharedStructs()) {
    std::vector<std::string> reads;
    for (const Member& member : shared.members) {
      reads.push_back(shared.prefix + member.name + (member.matrix ? "[0]" : ""));
    }
    const firn::gl::Program program = probe(shared.include, reads);
    for (const Member& member : shared.members) {
      const std::vector<GLint> values = properties(program, shared.interface, shared.prefix + member.name);
      ASSERT_FALSE(values.empty()) << "the driver reports no " << shared.prefix + member.name;
      EXPECT_EQ(std::size_t(values[0]), shared.baseBytes + member.offsetBytes) << shared.prefix + member.name;
    }
  }
}

TEST(GpuContract, ArraysStrideAsTheHostWritesThem) {
  const struct {
    const char* include;
    const char* name;
    std::size_t strideBytes;
  } arrays[] = {{"common/bindings.glsl", "materials[0].elastic", sizeof(MaterialParams)},
                {"common/particles.glsl", "plasticState[0].plasticJ", sizeof(ParticlePlasticState)},
                {"common/colliders.glsl", "colliders[0].shapeA", sizeof(ColliderParams)},
                {"common/blocks.glsl", "slots[0].block", sizeof(BlockSlot)},
                {"common/watchdog.glsl", "objectLoads[0].low", sizeof(ObjectLoad)},
                {"surface/vertices.glsl", "vertices[0].positionM", sizeof(SurfaceVertex)},
                {"surface/node_sums.glsl", "nodeSums[0].color", sizeof(SurfaceNodeSums)}};
  for (const auto& array : arrays) {
    const std::vector<GLint> values = properties(probe(array.include, {array.name}), GL_BUFFER_VARIABLE, array.name);
    ASSERT_FALSE(values.empty()) << array.name;
    EXPECT_EQ(std::size_t(values[3]), array.strideBytes) << array.name;
  }
  // Particle matrices are std430 mat3: three vec4 columns (gpu::Mat3x4); positions and velocities are vec4.
  const firn::gl::Program particles =
      probe("common/particles.glsl", {"positionMass[0]", "velocityVolume[0]", "elasticDeformation[0][0]",
                                      "kirchhoffStress[0][0]", "affine[0][0]"});
  for (const char* matrix : {"elasticDeformation[0]", "kirchhoffStress[0]", "affine[0]"}) {
    const std::vector<GLint> values = properties(particles, GL_BUFFER_VARIABLE, matrix);
    ASSERT_FALSE(values.empty()) << matrix;
    EXPECT_EQ(std::size_t(values[1]), sizeof(Mat3x4)) << matrix;
    EXPECT_EQ(std::size_t(values[2]), sizeof(Mat3x4::columns[0])) << matrix;
  }
  for (const char* vector : {"positionMass[0]", "velocityVolume[0]"}) {
    const std::vector<GLint> values = properties(particles, GL_BUFFER_VARIABLE, vector);
    ASSERT_FALSE(values.empty()) << vector;
    EXPECT_EQ(std::size_t(values[1]), sizeof(glm::vec4)) << vector;
  }
}

TEST(GpuContract, BlocksAreBoundWhereTheHostBindsThem) {
  const struct {
    const char* include;
    const char* read;  // something the block holds, so that the driver reports the block
    GLenum interface;
    const char* block;
    int binding;
    std::size_t bytes;  // the block's fixed part; 0 where it is only an unsized array
  } blocks[] = {
      {"common/bindings.glsl", "gridNodes", GL_UNIFORM_BLOCK, "StepUniformsBlock", FIRN_BINDING_STEP_UNIFORMS,
       sizeof(StepUniforms)},
      {"common/bindings.glsl", "materials[0].model", GL_SHADER_STORAGE_BLOCK, "MaterialsBuffer",
       FIRN_BINDING_MATERIALS, 0},
      // The status and the ledger, then the objects' loads: the driver counts one element of that array.
      {"common/watchdog.glsl", "overflowCount", GL_SHADER_STORAGE_BLOCK, "WatchdogBuffer", FIRN_BINDING_WATCHDOG,
       sizeof(WatchdogStatus) + sizeof(EnergyLedger) + sizeof(ObjectLoad)},
      {"common/colliders.glsl", "colliders[0].shapeA", GL_SHADER_STORAGE_BLOCK, "CollidersBuffer",
       FIRN_BINDING_COLLIDERS, 0},
      {"common/particles.glsl", "positionMass[0]", GL_SHADER_STORAGE_BLOCK, "PositionMassBuffer",
       FIRN_BINDING_POSITION_MASS, 0},
      {"common/particles.glsl", "velocityVolume[0]", GL_SHADER_STORAGE_BLOCK, "VelocityVolumeBuffer",
       FIRN_BINDING_VELOCITY_VOLUME, 0},
      {"common/particles.glsl", "elasticDeformation[0][0]", GL_SHADER_STORAGE_BLOCK, "ElasticDeformationBuffer",
       FIRN_BINDING_ELASTIC_DEFORMATION, 0},
      {"common/particles.glsl", "kirchhoffStress[0][0]", GL_SHADER_STORAGE_BLOCK, "KirchhoffStressBuffer",
       FIRN_BINDING_KIRCHHOFF_STRESS, 0},
      {"common/particles.glsl", "affine[0][0]", GL_SHADER_STORAGE_BLOCK, "AffineBuffer", FIRN_BINDING_AFFINE, 0},
      {"common/particles.glsl", "plasticState[0].plasticJ", GL_SHADER_STORAGE_BLOCK, "PlasticStateBuffer",
       FIRN_BINDING_PLASTIC_STATE, 0},
      {"common/grid.glsl", "gridMomentumMass[0]", GL_SHADER_STORAGE_BLOCK, "GridMomentumMassBuffer",
       FIRN_BINDING_GRID_MOMENTUM_MASS, 0},
      {"common/blocks.glsl", "blockCounts", GL_SHADER_STORAGE_BLOCK, "BlockTableBuffer", FIRN_BINDING_BLOCK_TABLE, 0},
      {"common/blocks.glsl", "blockMap[0]", GL_SHADER_STORAGE_BLOCK, "BlockMapBuffer", FIRN_BINDING_BLOCK_MAP, 0},
      {"common/blocks.glsl", "bins[0]", GL_SHADER_STORAGE_BLOCK, "BinsBuffer", FIRN_BINDING_BINS, 0},
      {"common/blocks.glsl", "sortedParticles[0]", GL_SHADER_STORAGE_BLOCK, "SortedParticlesBuffer",
       FIRN_BINDING_SORTED_PARTICLES, 0},
      {"common/blocks.glsl", "particleRanks[0]", GL_SHADER_STORAGE_BLOCK, "ParticleRanksBuffer",
       FIRN_BINDING_PARTICLE_RANKS, 0},
      {"common/blocks.glsl", "tileOrder[0]", GL_SHADER_STORAGE_BLOCK, "TileOrderBuffer", FIRN_BINDING_TILE_ORDER, 0},
      {"surface/surface_common.glsl", "boxNodes", GL_UNIFORM_BLOCK, "SurfaceUniformsBlock",
       FIRN_BINDING_SURFACE_UNIFORMS, sizeof(SurfaceUniforms)},
      {"surface/header.glsl", "kernelNodesMin", GL_SHADER_STORAGE_BLOCK, "SurfaceHeaderBuffer",
       FIRN_BINDING_SURFACE_HEADER, sizeof(SurfaceHeader)},
      {"surface/vertices.glsl", "vertices[0].normal", GL_SHADER_STORAGE_BLOCK, "SurfaceVertexBuffer",
       FIRN_BINDING_SURFACE_VERTICES, 0},
      {"surface/node_sums.glsl", "nodeSums[0].velocity", GL_SHADER_STORAGE_BLOCK, "SurfaceNodeSumsBuffer",
       FIRN_BINDING_SURFACE_SUMS, 0},
      {"common/solver.glsl", "solverNodes[0].residual", GL_SHADER_STORAGE_BLOCK, "SolverNodesBuffer",
       FIRN_BINDING_SOLVER_NODES, 0},
      {"common/solver.glsl", "solverPreconditioners[0].inverseDiagonal", GL_SHADER_STORAGE_BLOCK,
       "SolverPreconditionerBuffer", FIRN_BINDING_SOLVER_PRECONDITIONER, 0},
      {"common/material_hessians.glsl", "solverParticles[0].left[0]", GL_SHADER_STORAGE_BLOCK,
       "SolverParticlesBuffer", FIRN_BINDING_SOLVER_PARTICLES, 0},
      // The status, then the blocks' partial sums from its end: the driver counts one element of that array.
      {"common/solver_reduction.glsl", "registers[0]", GL_SHADER_STORAGE_BLOCK, "SolverStatusBuffer",
       FIRN_BINDING_SOLVER_STATUS, sizeof(SolverStatus) + sizeof(glm::vec4)},
      // The contact slots, then the bodies' records from their end: one record counted.
      {"common/body_blocks.glsl", "bodyRecords[0].velocity[0]", GL_SHADER_STORAGE_BLOCK, "BodiesBuffer",
       FIRN_BINDING_BODIES, CONTACT_SLOTS * sizeof(BodyContact) + sizeof(BodyRecord)},
  };
  for (const auto& block : blocks) {
    const firn::gl::Program program = probe(block.include, {block.read});
    EXPECT_EQ(blockProperty(program, block.interface, block.block, GL_BUFFER_BINDING), block.binding) << block.block;
    if (block.bytes > 0) {
      EXPECT_EQ(blockProperty(program, block.interface, block.block, GL_BUFFER_DATA_SIZE), GLint(block.bytes))
          << block.block;
    }
  }
}

TEST(GpuContractPasses, ParticlePassesRunInTheGroupsTheHostDispatches) {
  firn::test::glContext();
  const firn::gl::ShaderLibrary library;
  firn::gl::ShaderOptions options;
  options.defines = {{"FIRN_KERNEL_QUADRATIC", "1"}, {"FIRN_TRANSFER_APIC", "1"}, {"FIRN_WALL_CELLS", "2"}};
  for (const char* pass : {"sim/mark_blocks.comp", "sim/compute_volumes.comp"}) {
    const firn::gl::Program program = firn::gl::Program::compute(library, pass, options);
    GLint size[3] = {0, 0, 0};
    glGetProgramiv(program.id(), GL_COMPUTE_WORK_GROUP_SIZE, size);
    EXPECT_EQ(size[0] * size[1] * size[2], FIRN_PARTICLE_GROUP_SIZE) << pass;
  }
}

}  // namespace

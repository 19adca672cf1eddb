// Every program Firn builds, as the driver receives it, compiled by Khronos' reference front end (glslangValidator,
// Debian's glslang-tools) with no error and no warning, and each stage's resources held to the limits Firn states
// (the FIRN_REQUIRED_* lines of common/gpu_contract.h, docs/platform.md's Limits).
//
// The programs are not listed here: they are recorded (gl::ShaderSourceLog) while production code builds them, the
// step's for scenes that vary every option it is built for (kernel, transfer, atomics, material set, integrator,
// adaptive steps, colliders), the renderer's and the surface's for scenes of one and of several materials. A switch
// that a shader tests but that no recorded program sets and no shader defines (a test's variant of a pass) is built
// into every recorded stage that tests it. Every .comp, .vert, .frag and .geom file under shaders/ must be among
// the recorded stages, so that a new shader cannot be missed.
#include <gtest/gtest.h>

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "GlTest.h"
#include "gl/Limits.h"
#include "gl/Program.h"
#include "gl/StorageAccess.h"
#include "render/Renderer.h"
#include "scene/Scene.h"
#include "sim/BlockGrid.h"
#include "sim/StepPipeline.h"
#include "surface/SurfaceReconstruction.h"

namespace {

namespace fs = std::filesystem;
using firn::Scene;
using firn::gl::ShaderOptions;
using firn::gl::ShaderSourceLog;

// One stage to compile: what the driver received, from where.
using Stage = ShaderSourceLog::Stage;

std::string describe(const ShaderOptions& options) {
  std::string text;
  for (const auto& extension : options.extensions) text += " +" + extension;
  for (const auto& [name, value] : options.defines) text += " " + name + (value == "1" ? "" : "=" + value);
  return text;
}

const char* stageSuffix(GLenum type) {
  switch (type) {
    case GL_COMPUTE_SHADER: return "comp";
    case GL_VERTEX_SHADER: return "vert";
    case GL_FRAGMENT_SHADER: return "frag";
    case GL_GEOMETRY_SHADER: return "geom";
    default: return "unknown";
  }
}

// The scenes whose programs are recorded: the built-in scene with each option of the step varied, so that every
// value of every option is built at least once, and each with the others it interacts with (kernel × transfer ×
// atomics; the integrator × kernel × transfer, with and without adaptive steps).
std::vector<std::pair<Scene, firn::MaterialPrograms>> stepScenes() {
  using namespace firn;
  const Scene base = defaultScene();
  const auto withModels = [&](Scene scene, std::vector<MaterialModel> models) {
    scene.materials.clear();
    for (const MaterialModel model : models) {
      Material material = base.materials.front();
      material.model = model;
      if (model == MaterialModel::Water) material.bulkModulusPa = 1e5;
      scene.materials.push_back(material);
    }
    return scene;
  };
  const std::vector<MaterialModel> everyModel = {MaterialModel::Snow, MaterialModel::FixedCorotated,
                                                 MaterialModel::NeoHookean, MaterialModel::Water,
                                                 MaterialModel::DruckerPrager};
  const std::vector<MaterialModel> withHessian = {MaterialModel::Snow, MaterialModel::FixedCorotated,
                                                  MaterialModel::NeoHookean};
  std::vector<std::pair<Scene, MaterialPrograms>> scenes;
  for (const Kernel kernel : {Kernel::Quadratic, Kernel::Cubic}) {
    for (const Transfer transfer : {Transfer::PicFlip, Transfer::Apic}) {
      for (const Atomics atomics : {Atomics::FixedPoint, Atomics::Float}) {
        Scene scene = base;
        scene.solver.kernel = kernel;
        scene.solver.transfer = transfer;
        scene.solver.atomics = atomics;
        scenes.emplace_back(scene, MaterialPrograms::SceneModels);
      }
      for (const bool adaptive : {false, true}) {
        Scene scene = withModels(base, withHessian);
        scene.solver.kernel = kernel;
        scene.solver.transfer = transfer;
        scene.solver.integrator = Integrator::SemiImplicit;
        scene.time.adaptive = adaptive;
        scenes.emplace_back(scene, MaterialPrograms::SceneModels);
      }
    }
  }
  for (const MaterialModel model : everyModel) scenes.emplace_back(withModels(base, {model}), MaterialPrograms::SceneModels);
  scenes.emplace_back(withModels(base, everyModel), MaterialPrograms::SceneModels);
  scenes.emplace_back(base, MaterialPrograms::EveryModel);
  Scene withoutColliders = base;
  withoutColliders.colliders.clear();
  scenes.emplace_back(withoutColliders, MaterialPrograms::SceneModels);
  Scene adaptiveExplicit = base;
  adaptiveExplicit.time.adaptive = true;
  scenes.emplace_back(adaptiveExplicit, MaterialPrograms::SceneModels);
  Scene semiImplicitFloat = withModels(base, withHessian);
  semiImplicitFloat.solver.integrator = Integrator::SemiImplicit;
  semiImplicitFloat.solver.atomics = Atomics::Float;
  scenes.emplace_back(semiImplicitFloat, MaterialPrograms::SceneModels);
  // Objects: a mesh collider alone (the distance fields), then with a rigid body (the bodies' pushes and passes), and
  // with water and a second body too (the images of its stress: RigidBodies.h, mirrorsStressIntoBodies; the bodies'
  // contacts with each other within the coupled solve).
  Scene withMeshCollider = base;
  Collider mesh;
  mesh.shape = ColliderShape::Mesh;
  withMeshCollider.colliders.push_back(mesh);
  scenes.emplace_back(withMeshCollider, MaterialPrograms::SceneModels);
  Scene withRigidBody = withMeshCollider;
  RigidBody ball;
  ball.radiusM = 0.1;
  withRigidBody.rigidBodies.push_back(ball);
  scenes.emplace_back(withRigidBody, MaterialPrograms::SceneModels);
  Scene withTwoBodiesAndWater = withModels(withRigidBody, {MaterialModel::Snow, MaterialModel::Water});
  RigidBody secondBall = ball;
  secondBall.centerM = ball.centerM + glm::dvec3(0.3, 0.0, 0.0);
  secondBall.centerOfMassM = secondBall.centerM;
  withTwoBodiesAndWater.rigidBodies.push_back(secondBall);
  scenes.emplace_back(withTwoBodiesAndWater, MaterialPrograms::SceneModels);
  // The semi-implicit step's pushes to a rigid body (solver_solution.comp and the passes that push).
  Scene semiImplicitWithRigidBody = withModels(withRigidBody, withHessian);
  semiImplicitWithRigidBody.solver.integrator = Integrator::SemiImplicit;
  scenes.emplace_back(semiImplicitWithRigidBody, MaterialPrograms::SceneModels);
  return scenes;
}

// The FIRN_ macros a source tests in #if, #ifdef, #ifndef or #elif lines, and those it #defines.
std::set<std::string> macrosMatching(const std::string& text, const std::regex& line, bool firstOnly) {
  static const std::regex name(R"(\bFIRN_\w+)");
  std::set<std::string> names;
  std::istringstream lines(text);
  std::string current;
  while (std::getline(lines, current)) {
    std::smatch match;
    if (!std::regex_search(current, match, line)) continue;
    const std::string rest = match.suffix().str();
    for (auto it = std::sregex_iterator(rest.begin(), rest.end(), name); it != std::sregex_iterator(); ++it) {
      names.insert(it->str());
      if (firstOnly) break;  // a #define names one macro; what follows is its value
    }
  }
  return names;
}

std::set<std::string> testedMacros(const std::string& text) {
  static const std::regex conditional(R"(^\s*#\s*(if|ifdef|ifndef|elif)\b)");
  return macrosMatching(text, conditional, false);
}

std::set<std::string> definedMacros(const std::string& text) {
  static const std::regex define(R"(^\s*#\s*define\b)");
  return macrosMatching(text, define, true);
}

// Every stage production builds for the scenes above, then the test variants, without duplicates.
std::vector<Stage> recordStages() {
  const firn::gl::ContextInfo& info = firn::test::glContext().info();
  std::vector<Stage> stages;
  {
    ShaderSourceLog log;
    // A step's programs: the pipeline's and the block grid's, which sort the particles into it.
    for (const auto& [scene, programs] : stepScenes()) {
      firn::StepPipeline pipeline(scene, programs, info, firn::transferShapeCandidates(scene, ""));
      const firn::GpuStateLayout layout =
          firn::GpuStateLayout::forScene(scene, 1, 1, firn::needsDeformationGradient(scene, programs));
      firn::BlockGrid grid(layout, firn::gl::ShaderLibrary(), firn::stepShaderOptions(scene, programs), info);
      // The passes a share builds: at its first migration (BlockGrid::particlesOutside), and with rigid bodies the
      // claims of their images' blocks (BlockGrid::claimImageBlocks).
      const firn::gl::ComputePass listLeavers(firn::gl::ShaderLibrary(), "sim/list_leavers.comp",
                                              firn::stepShaderOptions(scene, programs));
      if (!scene.rigidBodies.empty()) grid.claimImageBlocks();
    }
    Scene severalMaterials = firn::defaultScene();
    severalMaterials.materials.push_back(severalMaterials.materials.front());
    for (const Scene& scene : {firn::defaultScene(), severalMaterials}) {
      firn::render::Renderer renderer(scene);
      firn::surface::SurfaceReconstruction surface(scene, {}, info);
    }
    stages = log.stages();
  }
  // Switches no production build sets and no shader defines: each is a variant some test builds.
  std::set<std::string> setOrDefined;
  for (const auto& [path, text] : firn::gl::embeddedShaderFiles()) {
    const std::set<std::string> defined = definedMacros(text);
    setOrDefined.insert(defined.begin(), defined.end());
  }
  for (const Stage& stage : stages) {
    for (const auto& define : stage.options.defines) setOrDefined.insert(define.first);
  }
  const firn::gl::ShaderLibrary library;
  std::vector<Stage> variants;
  std::set<std::string> variantNames;
  for (const Stage& stage : stages) {
    for (const std::string& macro : testedMacros(stage.source.text)) {
      if (setOrDefined.count(macro) != 0) continue;
      ShaderOptions options = stage.options;
      options.defines.emplace_back(macro, "1");
      variants.push_back({stage.type, stage.path, options, library.preprocess(stage.path, options)});
      variantNames.insert(stage.path + " with " + macro);
    }
  }
  for (const std::string& name : variantNames) std::printf("test variant: %s\n", name.c_str());
  stages.insert(stages.end(), variants.begin(), variants.end());
  std::vector<Stage> unique;
  std::set<std::string> seen;
  for (const Stage& stage : stages) {
    if (seen.insert(stage.source.text).second) unique.push_back(stage);
  }
  return unique;
}

// What glslang's AST dump (-i) lists among a stage's linker objects, which hold every global it declares, used
// or not (Mesa counts declared storage blocks against its limits, docs/platform.md).
struct Resources {
  int storageBlocks = 0;
  int highestStorageBinding = -1;
  long long sharedBytes = 0;
  int invocations = 1;
  std::string localSize;
};

// The std430 size and alignment of a glslang type name ("256-element array of 4-component vector of uint"): an
// upper bound on what a driver gives a shared variable. Throws for a type it cannot size.
std::pair<long long, long long> std430SizeAndAlignment(const std::string& type) {
  std::smatch match;
  static const std::regex array(R"(^(\d+)-element array of (.*)$)");
  static const std::regex vector(R"(^(\d+)-component vector of (\w+)$)");
  static const std::regex matrix(R"(^(\d+)X(\d+) matrix of (\w+)$)");
  const auto scalarBytes = [&](const std::string& scalar) -> long long {
    if (scalar == "float" || scalar == "int" || scalar == "uint" || scalar == "bool") return 4;
    if (scalar == "double" || scalar == "int64_t" || scalar == "uint64_t") return 8;
    throw std::runtime_error("cannot size shared type \"" + type + "\"");
  };
  if (std::regex_match(type, match, array)) {
    const auto [size, alignment] = std430SizeAndAlignment(match[2].str());
    const long long stride = (size + alignment - 1) / alignment * alignment;
    return {std::stoll(match[1].str()) * stride, alignment};
  }
  if (std::regex_match(type, match, vector)) {
    const long long components = std::stoll(match[1].str());
    const long long scalar = scalarBytes(match[2].str());
    return {components * scalar, (components == 2 ? 2 : 4) * scalar};
  }
  if (std::regex_match(type, match, matrix)) {  // columns X rows, each column a vector
    const long long rows = std::stoll(match[2].str());
    const long long scalar = scalarBytes(match[3].str());
    const long long column = (rows == 2 ? 2 : 4) * scalar;
    return {std::stoll(match[1].str()) * column, column};
  }
  const long long scalar = scalarBytes(type);
  return {scalar, scalar};
}

Resources parseResources(const std::string& dump) {
  Resources resources;
  static const std::regex localSize(R"(^local_size = \((\d+), (\d+), (\d+)\))");
  static const std::regex object(R"(^0:\?     '[^']*' \((.*)\)$)");
  static const std::regex layout(R"(^layout\(([^)]*)\)\s*)");
  static const std::regex binding(R"(\bbinding=(\d+))");
  static const std::regex blockArray(R"(^(\d+)-element array of block\{)");
  std::istringstream lines(dump);
  std::string line;
  bool inLinkerObjects = false;
  while (std::getline(lines, line)) {
    std::smatch match;
    if (std::regex_search(line, match, localSize)) {
      resources.localSize = match[1].str() + "×" + match[2].str() + "×" + match[3].str();
      resources.invocations = std::stoi(match[1].str()) * std::stoi(match[2].str()) * std::stoi(match[3].str());
    }
    if (line.find("Linker Objects") != std::string::npos) inLinkerObjects = true;
    if (!inLinkerObjects || !std::regex_match(line, match, object)) continue;
    std::string declaration = match[1].str();
    int firstBinding = -1;
    if (std::regex_search(declaration, match, layout)) {
      const std::string qualifiers = match[1].str();
      declaration = match.suffix().str();
      std::smatch bindingMatch;
      if (std::regex_search(qualifiers, bindingMatch, binding)) firstBinding = std::stoi(bindingMatch[1].str());
    }
    // The qualifiers before the type: "buffer", "shared", "uniform", memory qualifiers.
    const std::string head = declaration.substr(0, declaration.find('{'));
    std::istringstream words(head);
    std::set<std::string> qualifiers;
    for (std::string word; words >> word;) qualifiers.insert(word);
    if (qualifiers.count("buffer") != 0) {
      const std::string type = declaration.substr(declaration.find("buffer") + 7);
      const int count = std::regex_search(type, match, blockArray) ? std::stoi(match[1].str()) : 1;
      resources.storageBlocks += count;
      resources.highestStorageBinding = std::max(resources.highestStorageBinding, firstBinding + count - 1);
    } else if (qualifiers.count("shared") != 0) {
      const std::string type = declaration.substr(declaration.find("shared") + 7);
      resources.sharedBytes += std430SizeAndAlignment(type).first;
    }
  }
  return resources;
}

// Rewrites glslang's "ERROR: 0:LINE:" and "WARNING: 0:LINE:" to the original file:line.
std::string mapLog(const std::string& log, const Stage& stage) {
  static const std::regex location(R"(((?:ERROR|WARNING): )0:(\d+):)");
  std::string result;
  auto begin = log.cbegin();
  std::smatch match;
  while (std::regex_search(begin, log.cend(), match, location)) {
    result.append(begin, match[0].first);
    const std::size_t line = std::stoul(match[2].str());
    result += match[1].str();
    if (line >= 1 && line <= stage.source.origins.size()) {
      const auto& origin = stage.source.origins[line - 1];
      result += origin.file + ":" + std::to_string(origin.line) + ":";
    } else {
      result += match[0].str().substr(match[1].length());
    }
    begin = match[0].second;
  }
  result.append(begin, log.cend());
  return result;
}

std::string readFile(const fs::path& path) {
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  return text.str();
}

// glslang (12.0, Debian 12) does not know GL_NV_shader_atomic_float, which `"atomics": "float"` enables for its
// atomicAdd on float buffer members. It knows GL_EXT_shader_atomic_float, which declares those same overloads (and
// more), from GLSL 4.50 on. So a stage that requires the NV extension is checked as GLSL 4.50 with the EXT extension
// in its place; everything else in it is what the driver receives.
std::string asGlslangReadsIt(const Stage& stage) {
  const std::string nv = "#extension GL_NV_shader_atomic_float : require\n";
  std::string text = stage.source.text;
  const std::size_t at = text.find(nv);
  if (at == std::string::npos) return text;
  text.replace(at, nv.size(), "#extension GL_EXT_shader_atomic_float : require\n");
  const std::size_t versionEnd = text.find('\n');
  EXPECT_EQ(text.substr(0, versionEnd), "#version 430 core") << stage.path;
  text.replace(0, versionEnd, "#version 450 core");
  return text;
}

long long required(const std::string& glLimit) {
  for (const auto& requirement : firn::gl::requiredLimits()) {
    if (requirement.glLimit == glLimit) return requirement.required;
  }
  ADD_FAILURE() << "common/gpu_contract.h states no requirement for " << glLimit;
  return 0;
}

TEST(Portability, EveryProgramCompilesWithGlslangAndFitsTheStatedLimits) {
  const std::string glslang = FIRN_GLSLANG_VALIDATOR;
  ASSERT_FALSE(glslang.empty() || glslang.find("NOTFOUND") != std::string::npos)
      << "glslangValidator was not found when configuring: install glslang-tools (scripts/setup.sh)";
  const auto started = std::chrono::steady_clock::now();
  const std::vector<Stage> stages = recordStages();

  // Every stage file under shaders/ is among them.
  std::set<std::string> built;
  for (const Stage& stage : stages) built.insert(stage.path);
  static const std::regex stageFile(R"(.*\.(comp|vert|frag|geom)$)");
  for (const auto& [path, text] : firn::gl::embeddedShaderFiles()) {
    if (std::regex_match(path, stageFile)) {
      EXPECT_EQ(built.count(path), 1u) << path << " is built by none of the recorded programs";
    }
  }

  char folderTemplate[] = "/tmp/firn-glslang-XXXXXX";
  ASSERT_NE(mkdtemp(folderTemplate), nullptr);
  const fs::path folder = folderTemplate;
  std::vector<fs::path> files;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    files.push_back(folder / (std::to_string(i) + "." + stageSuffix(stages[i].type)));
    std::ofstream(files.back()) << asGlslangReadsIt(stages[i]);
  }
  // glslang's start costs more than a stage's compile (measured: 0.19 s for one stage, 0.43 s for ten), so each
  // run compiles 40 stages, each under a line with its file name; two runs at a time, for the test machines' two
  // cores. A run's exit status says only whether all of its stages compiled: each stage's own lines are read below.
  const auto recorded = std::chrono::steady_clock::now();
  const std::string command = "cd '" + folder.string() + "' && ls | grep -v '\\.log$' | xargs -n 40 -P 2 sh -c '\"" + glslang +
                              "\" -i \"$@\" > run_$$.log 2>&1; true' sh";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  std::map<std::string, std::string> logs;  // by file name
  static const std::regex fileLine(R"(\d+\.(comp|vert|frag|geom))");
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (entry.path().extension() != ".log") continue;
    std::istringstream lines(readFile(entry.path()));
    std::string* current = nullptr;
    for (std::string line; std::getline(lines, line);) {
      if (std::regex_match(line, fileLine)) {
        current = &logs[line];
      } else if (current != nullptr) {
        *current += line + "\n";
      }
    }
  }

  const long long storageBindings = required("GL_MAX_SHADER_STORAGE_BUFFER_BINDINGS");
  const std::map<GLenum, long long> storageBlocks = {
      {GL_COMPUTE_SHADER, required("GL_MAX_COMPUTE_SHADER_STORAGE_BLOCKS")},
      {GL_VERTEX_SHADER, required("GL_MAX_VERTEX_SHADER_STORAGE_BLOCKS")},
      {GL_FRAGMENT_SHADER, required("GL_MAX_FRAGMENT_SHADER_STORAGE_BLOCKS")}};
  const long long sharedBytes = required("GL_MAX_COMPUTE_SHARED_MEMORY_SIZE");
  const long long invocations = required("GL_MAX_COMPUTE_WORK_GROUP_INVOCATIONS");

  // The resource table, one row per distinct stage file: the most any of its builds declares.
  std::map<std::string, Resources> table;
  for (std::size_t i = 0; i < stages.size(); ++i) {
    const Stage& stage = stages[i];
    const std::string what = stage.path + " with" + describe(stage.options);
    const auto found = logs.find(files[i].filename().string());
    ASSERT_NE(found, logs.end()) << what << ": glslang said nothing of " << files[i];
    const std::string& log = found->second;
    EXPECT_EQ(log.find("ERROR"), std::string::npos) << what << ":\n" << mapLog(log, stage);
    EXPECT_EQ(log.find("WARNING"), std::string::npos) << what << ":\n" << mapLog(log, stage);
    const Resources resources = parseResources(log);
    const auto limit = storageBlocks.find(stage.type);
    ASSERT_NE(limit, storageBlocks.end()) << what << ": no storage block limit is stated for this stage";
    EXPECT_LE(resources.storageBlocks, limit->second) << what;
    EXPECT_LT(resources.highestStorageBinding, storageBindings) << what;
    EXPECT_LE(resources.sharedBytes, sharedBytes) << what;
    EXPECT_LE(resources.invocations, invocations) << what;
    if (stage.type == GL_COMPUTE_SHADER) {
      EXPECT_FALSE(resources.localSize.empty()) << what << ": no local_size";
    }
    Resources& row = table[stage.path];
    row.storageBlocks = std::max(row.storageBlocks, resources.storageBlocks);
    row.highestStorageBinding = std::max(row.highestStorageBinding, resources.highestStorageBinding);
    row.sharedBytes = std::max(row.sharedBytes, resources.sharedBytes);
    row.invocations = std::max(row.invocations, resources.invocations);
    if (row.localSize.empty()) row.localSize = resources.localSize;
  }
  const auto seconds = [](auto from, auto to) { return std::chrono::duration<double>(to - from).count(); };
  std::printf("%zu distinct stages recorded in %.1f s, compiled by %s in %.1f s\n%-34s %7s %8s %7s %s\n",
              stages.size(), seconds(started, recorded), glslang.c_str(),
              seconds(recorded, std::chrono::steady_clock::now()), "stage", "blocks", "binding", "shared",
              "work group");
  for (const auto& [path, row] : table) {
    std::printf("%-34s %7d %8d %7lld %s\n", path.c_str(), row.storageBlocks, row.highestStorageBinding, row.sharedBytes,
                row.localSize.c_str());
  }
  if (!HasFailure()) fs::remove_all(folder);
}

// The storage blocks whose members a SPIR-V module (as spirv-dis writes it, --raw-id) stores to or changes by an
// atomic, by the blocks' type names ("PositionMassBuffer"): pointers traced from the blocks' variables through access
// chains to the OpStore and OpAtomic* that use them.
std::set<std::string> writtenBlocks(const std::string& disassembly) {
  static const std::regex name(R"re(^\s*OpName (%\d+) "([^"]*)")re");
  static const std::regex bufferBlock(R"(^\s*OpDecorate (%\d+) (?:BufferBlock|Block)\b)");
  static const std::regex pointerType(R"(^\s*(%\d+) = OpTypePointer (\w+) (%\d+))");
  static const std::regex variable(R"(^\s*(%\d+) = OpVariable (%\d+) (Uniform|StorageBuffer)\b)");
  static const std::regex chain(R"(^\s*(%\d+) = Op(?:InBounds)?(?:Ptr)?AccessChain %\d+ (%\d+))");
  static const std::regex store(R"(^\s*OpStore (%\d+) )");
  static const std::regex atomic(R"(^\s*(?:%\d+ = )?OpAtomic(\w+) (?:%\d+ )?(%\d+))");
  std::map<std::string, std::string> names, pointee, blockOf;
  std::set<std::string> blocks, written;
  std::vector<std::string> lines;
  std::istringstream text(disassembly);
  for (std::string line; std::getline(text, line);) lines.push_back(line);
  std::smatch match;
  for (const std::string& line : lines) {
    if (std::regex_search(line, match, name)) names[match[1]] = match[2];
    if (std::regex_search(line, match, bufferBlock)) blocks.insert(match[1]);
    if (std::regex_search(line, match, pointerType)) pointee[match[1]] = match[3];
  }
  for (const std::string& line : lines) {
    if (std::regex_search(line, match, variable) && blocks.count(pointee[match[2]]) != 0) {
      blockOf[match[1]] = names[pointee[match[2]]];
    } else if (std::regex_search(line, match, chain) && blockOf.count(match[2]) != 0) {
      blockOf[match[1]] = blockOf[match[2]];
    } else if (std::regex_search(line, match, store) && blockOf.count(match[1]) != 0) {
      written.insert(blockOf[match[1]]);
    } else if (std::regex_search(line, match, atomic) && match[1] != "Load" && blockOf.count(match[2]) != 0) {
      written.insert(blockOf[match[2]]);
    }
  }
  return written;
}

// Every pass of the step writes only the storage blocks its header lists under Writes (gl/StorageAccess.h): the
// barriers follow from those lists, and a write left out would be a barrier left out, which no result on a driver that
// runs the passes in order shows. Each compute stage under sim/ that production and the tests build, as the driver
// receives it, compiled to SPIR-V for OpenGL by glslang, its stores and atomics traced to their blocks by spirv-dis.
TEST(Portability, EveryPassWritesOnlyWhatItsHeaderDeclares) {
  const std::string glslang = FIRN_GLSLANG_VALIDATOR, disassembler = FIRN_SPIRV_DIS;
  ASSERT_FALSE(glslang.find("NOTFOUND") != std::string::npos || disassembler.find("NOTFOUND") != std::string::npos)
      << "glslangValidator or spirv-dis was not found when configuring: install glslang-tools (scripts/setup.sh)";
  std::vector<Stage> passes;
  for (const Stage& stage : recordStages()) {
    if (stage.type == GL_COMPUTE_SHADER && stage.path.rfind("sim/", 0) == 0) passes.push_back(stage);
  }
  ASSERT_GE(passes.size(), 34u);
  char folderTemplate[] = "/tmp/firn-spirv-XXXXXX";
  ASSERT_NE(mkdtemp(folderTemplate), nullptr);
  const fs::path folder = folderTemplate;
  for (std::size_t i = 0; i < passes.size(); ++i) {
    std::ofstream(folder / (std::to_string(i) + ".comp")) << asGlslangReadsIt(passes[i]);
  }
  // One glslang and one spirv-dis per stage, two stages at a time.
  const std::string command = "cd '" + folder.string() + "' && ls *.comp | xargs -n 1 -P 2 sh -c '\"" + glslang +
                              "\" -G --target-env opengl --aml -S comp \"$0\" -o \"$0.spv\" > \"$0.log\" 2>&1 && \"" +
                              disassembler + "\" --raw-id \"$0.spv\" -o \"$0.dis\"; true'";
  ASSERT_EQ(std::system(command.c_str()), 0) << command;
  const firn::gl::ShaderLibrary library;
  for (std::size_t i = 0; i < passes.size(); ++i) {
    const Stage& stage = passes[i];
    const std::string what = stage.path + " with" + describe(stage.options);
    const fs::path file = folder / (std::to_string(i) + ".comp");
    ASSERT_TRUE(fs::exists(file.string() + ".dis")) << what << ":\n" << readFile(file.string() + ".log");
    const auto declared = firn::gl::declaredAccess(stage.path, library.file(stage.path));
    ASSERT_TRUE(declared.has_value()) << what;
    std::set<std::string> declaredWrites;
    for (const std::string& name : declared->writes) {
      declaredWrites.insert(std::string(1, char(std::toupper(static_cast<unsigned char>(name[0])))) + name.substr(1) +
                            "Buffer");
    }
    for (const std::string& block : writtenBlocks(readFile(file.string() + ".dis"))) {
      EXPECT_EQ(declaredWrites.count(block), 1u)
          << what << " writes " << block << ", which its Writes: line leaves out";
    }
  }
  if (!HasFailure()) fs::remove_all(folder);
}

// Each drawing program's vertex and fragment stages, as the driver received them, linked by glslang (-l): what
// one stage passes the other must match in name, type and qualifiers. Program::graphics compiles a program's vertex
// stage, then its fragment stage, so the log holds them one after the other.
TEST(Portability, EveryDrawingProgramLinksWithGlslang) {
  const std::string glslang = FIRN_GLSLANG_VALIDATOR;
  ASSERT_FALSE(glslang.empty() || glslang.find("NOTFOUND") != std::string::npos)
      << "glslangValidator was not found when configuring: install glslang-tools (scripts/setup.sh)";
  const firn::gl::ContextInfo& info = firn::test::glContext().info();
  std::vector<std::pair<Stage, Stage>> programs;
  {
    ShaderSourceLog log;
    Scene severalMaterials = firn::defaultScene();
    severalMaterials.materials.push_back(severalMaterials.materials.front());
    for (const Scene& scene : {firn::defaultScene(), severalMaterials}) {
      firn::render::Renderer renderer(scene);
      firn::surface::SurfaceReconstruction surface(scene, {}, info);
    }
    const auto& stages = log.stages();
    for (std::size_t i = 0; i < stages.size(); ++i) {
      if (stages[i].type != GL_VERTEX_SHADER) continue;
      ASSERT_LT(i + 1, stages.size()) << stages[i].path << " is not followed by a fragment stage";
      ASSERT_EQ(stages[i + 1].type, static_cast<GLenum>(GL_FRAGMENT_SHADER)) << stages[i].path;
      programs.emplace_back(stages[i], stages[i + 1]);
    }
  }
  ASSERT_FALSE(programs.empty()) << "the renderer built no drawing program";
  char folderTemplate[] = "/tmp/firn-glslang-link-XXXXXX";
  ASSERT_NE(mkdtemp(folderTemplate), nullptr);
  const fs::path folder = folderTemplate;
  std::set<std::string> seen;
  std::size_t linked = 0;
  for (const auto& [vertex, fragment] : programs) {
    if (!seen.insert(vertex.source.text + fragment.source.text).second) continue;
    const fs::path vertexFile = folder / (std::to_string(linked) + ".vert");
    const fs::path fragmentFile = folder / (std::to_string(linked) + ".frag");
    std::ofstream(vertexFile) << vertex.source.text;
    std::ofstream(fragmentFile) << fragment.source.text;
    const fs::path logFile = folder / (std::to_string(linked) + ".log");
    const std::string command = "\"" + glslang + "\" -l '" + vertexFile.string() + "' '" + fragmentFile.string() +
                                "' > '" + logFile.string() + "' 2>&1";
    const int status = std::system(command.c_str());
    const std::string log = readFile(logFile);
    const std::string what = vertex.path + " + " + fragment.path + " with" + describe(vertex.options);
    EXPECT_EQ(status, 0) << what << ":\n" << log;
    EXPECT_EQ(log.find("ERROR"), std::string::npos) << what << ":\n" << log;
    EXPECT_EQ(log.find("WARNING"), std::string::npos) << what << ":\n" << log;
    ++linked;
  }
  std::printf("%zu distinct drawing programs linked by %s\n", linked, glslang.c_str());
  if (!HasFailure()) fs::remove_all(folder);
}

// The parser of glslang's linker objects counts what a stage declares: a block it does not use, an array of
// blocks as one block per element, shared arrays by std430's strides.
TEST(Portability, ResourceTableCountsDeclaredBlocksAndSharedBytes) {
  const std::string dump =
      "local_size = (8, 8, 4)\n"
      "0:?   Linker Objects\n"
      "0:?     'gl_WorkGroupSize' ( const 3-component vector of uint WorkGroupSize)\n"
      "0:?       8 (const uint)\n"
      "0:?     'anon@0' (layout( binding=3 column_major std430) buffer block{layout( column_major std430 offset=0) "
      "buffer unsized 1-element array of 4-component vector of float a})\n"
      "0:?     'unused' (layout( binding=7 column_major std430) readonly buffer block{layout( column_major std430 "
      "offset=0) buffer unsized 1-element array of float u})\n"
      "0:?     'several' (layout( binding=20 column_major std430) buffer 3-element array of block{layout( "
      "column_major std430 offset=0) buffer float s})\n"
      "0:?     'anon@2' (layout( binding=1 column_major std140) uniform block{layout( column_major std140 offset=0) "
      "uniform 4-component vector of float x})\n"
      "0:?     'sums' ( shared 256-element array of 4-component vector of uint)\n"
      "0:?     'points' ( shared 10-element array of 3-component vector of float)\n"
      "0:?     'total' ( shared float)\n";
  const Resources resources = parseResources(dump);
  EXPECT_EQ(resources.storageBlocks, 5);
  EXPECT_EQ(resources.highestStorageBinding, 22);
  EXPECT_EQ(resources.sharedBytes, 256 * 16 + 10 * 16 + 4);  // a vec3 array's stride is 16 bytes under std430
  EXPECT_EQ(resources.invocations, 256);
  EXPECT_EQ(resources.localSize, "8×8×4");
}

}  // namespace

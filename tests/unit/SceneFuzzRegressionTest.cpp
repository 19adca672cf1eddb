// The scene parser's contract, as the fuzzer (tests/fuzz) checks it: any text either parses into a Scene or
// throws InputError (docs/command-line.md: bad input, exit status 2), promptly. Every input the fuzzer once broke
// it with is kept in tests/fuzz/regressions/ and replayed here, with hand-written inputs at the limits: deep
// nesting, numbers at the edges of a double, the largest grids, and files that are not regular files.
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <string>
#include <typeinfo>

#include <glm/vec3.hpp>
#include <gtest/gtest.h>

#include "Error.h"
#include "io/PointCloud.h"
#include "scene/Scene.h"

namespace firn {
namespace {

const std::filesystem::path fuzzFolder = std::filesystem::path(FIRN_SOURCE_DIR) / "tests" / "fuzz";
// The fuzzer parses its scenes as if they lay in tests/fuzz/files/ (SceneParserFuzz.cpp), and so do these
// tests, so that a kept input names the same small mesh and point clouds.
const std::filesystem::path sceneFile = fuzzFolder / "files" / "fuzz.json";

std::string readText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Parses `text`: a Scene or an InputError passes; any other exception fails, naming its type and message.
void expectParsesOrIsBadInput(const std::string& text, const std::string& what) {
  try {
    parseScene(text, sceneFile);
  } catch (const InputError&) {
  } catch (const std::exception& error) {
    ADD_FAILURE() << what << ": threw " << typeid(error).name() << ", not InputError: " << error.what();
  }
}

void expectParses(const std::string& text, const std::string& what) {
  try {
    parseScene(text, sceneFile);
  } catch (const std::exception& error) {
    ADD_FAILURE() << what << ": expected a scene, got: " << error.what();
  }
}

// The parse must fail with an InputError whose message says `problemFragment`.
void expectBadInput(const std::string& text, const std::string& problemFragment, const std::string& what) {
  try {
    parseScene(text, sceneFile);
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(problemFragment), std::string::npos)
        << what << ": message: " << error.what() << "\nexpected to contain: " << problemFragment;
    return;
  } catch (const std::exception& error) {
    ADD_FAILURE() << what << ": threw " << typeid(error).name() << ", not InputError: " << error.what();
    return;
  }
  ADD_FAILURE() << what << ": expected an InputError";
}

// A scene of wet snow with `grid` and `bodies` spliced in; smallGrid is 1 m of 16 cells a side (interior 0.125 to
// 0.875 m).
std::string scene(const std::string& grid, const std::string& bodies) {
  return R"({ "grid": )" + grid + R"(, "time": { "dt": 1e-3, "frame_rate": 30, "frames": 1 },
    "materials": { "snow": { "preset": "wet" } }, "bodies": [ )" + bodies + " ] }";
}
const std::string smallGrid = R"({ "cells": [16, 16, 16], "cell_size": 0.0625 })";
const std::string sphere = R"({ "shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.2, "material": "snow" })";

std::string pointsBody(const std::string& path, const std::string& placement = "") {
  return R"({ "shape": "points", "path": ")" + path + R"(", "material": "snow")" + placement + " }";
}

TEST(SceneFuzzRegression, EveryKeptInputParsesOrIsBadInput) {
  // Iterated, so that a new file is picked up without a change here; the folder may hold only its README.
  std::size_t inputs = 0;
  for (const auto& entry : std::filesystem::directory_iterator(fuzzFolder / "regressions")) {
    if (!entry.is_regular_file()) continue;
    expectParsesOrIsBadInput(readText(entry.path()), entry.path().filename().string());
    ++inputs;
  }
  EXPECT_GE(inputs, 1u) << "tests/fuzz/regressions/ holds at least its README";
}

// The fuzzer starts from these, so they should be valid scenes that reach every part of the loader.
TEST(SceneFuzzRegression, SeedCorpusScenesAreValid) {
  std::size_t seeds = 0;
  for (const auto& entry : std::filesystem::directory_iterator(fuzzFolder / "corpus")) {
    expectParses(readText(entry.path()), entry.path().filename().string());
    ++seeds;
  }
  EXPECT_GE(seeds, 1u);
}

// nlohmann's parse through a callback recurses with the nesting: 10,000 levels parse, but the issue's 150 KB of
// balanced brackets (153,600 levels) overflowed the stack (SIGSEGV). Arrays and objects deeper than
// kMaxNestingDepth are refused before nlohmann sees them, wherever the nest is and whether or not it is closed.
TEST(SceneFuzzRegression, DeepNestingIsBadInputWithoutExhaustingTheStack) {
  constexpr int depth = 150 * 1024;
  const std::string arrays = std::string(depth, '[') + std::string(depth, ']');
  std::string objects;
  for (int i = 0; i < depth; ++i) objects += R"({"a":)";
  objects += "0" + std::string(depth, '}');

  const std::string tooDeep = "nested more than 64 levels deep";
  expectBadInput(arrays, tooDeep, "nested arrays as the scene");
  expectBadInput(scene(smallGrid, sphere).insert(1, R"("gravity": )" + arrays + ","), tooDeep,
                 "nested arrays as the gravity");
  expectBadInput(scene(smallGrid, sphere).insert(1, R"("name": )" + objects + ","), tooDeep,
                 "nested objects as the name");
  expectBadInput(std::string(depth, '['), tooDeep, "unclosed nested arrays");
  expectBadInput(objects.substr(0, objects.size() - 1), tooDeep, "one object left unclosed");
  // At the limit the nest is the parser's to judge: here, no scene.
  expectBadInput(std::string(64, '[') + std::string(64, ']'), "expected an object", "64 nested arrays");
}

TEST(SceneFuzzRegression, NumbersAtTheEdgesOfADoubleParseOrAreBadInput) {
  // Numbers beyond a double are refused by the JSON reader.
  expectBadInput(scene(R"({ "cells": [16, 16, 16], "cell_size": 1e999 })", sphere), "must fit a double", "1e999");
  // The grid's far side and interior overflow to infinity; the body is then outside the interior.
  expectParsesOrIsBadInput(scene(R"({ "cells": [16, 16, 16], "cell_size": 1e308 })", sphere), "cell_size 1e308");
  expectParsesOrIsBadInput(
      scene(R"({ "origin": [-1e308, -1e308, -1e308], "cells": [1024, 1024, 1024], "cell_size": 1e308 })",
            R"({ "shape": "box", "min": [-1e307, -1e307, -1e307], "max": [1e308, 1e308, 1e308], "material": "snow" })"),
      "a box filling a grid of 1e308 m cells");
  expectParsesOrIsBadInput(scene(R"({ "cells": [16, 16, 16], "cell_size": 4.9e-324 })", sphere), "subnormal cell_size");
  expectParsesOrIsBadInput(R"({ "grid": { "cells": [16, 16, 16], "cell_size": 0.0625 },
    "time": { "dt": 4.9e-324, "frame_rate": 4.9e-324, "frames": 1000000 },
    "materials": { "snow": { "preset": "wet" } }, "bodies": [ )" + sphere + " ] }",
                           "subnormal dt and frame_rate");
  expectBadInput(scene(R"({ "cells": [16, 16, 1e308], "cell_size": 0.0625 })", sphere), "must be in [8, 1024]",
                 "1e308 cells");
  expectBadInput(scene(R"({ "cells": [16, 16, 2147483648], "cell_size": 0.0625 })", sphere), "must be in [8, 1024]",
                 "cells beyond an int");
  expectParsesOrIsBadInput(
      scene(smallGrid, R"({ "shape": "mesh", "path": "tetrahedron.obj", "scale": 1e308, "material": "snow" })"),
      "a mesh scaled by 1e308");
}

// Sampling happens later (sampleBodies), so even the largest grid and body parse at once.
TEST(SceneFuzzRegression, LargestGridAndDensestSamplingParseWithoutSampling) {
  const std::string largestGrid = R"({ "cells": [1024, 1024, 1024], "cell_size": 0.01 })";
  expectParses(scene(largestGrid, R"({ "shape": "sphere", "center": [5.12, 5.12, 5.12], "radius": 5,
                                       "material": "snow", "particles_per_cell": 1000 })"),
               "a 1024³ grid filled by a sphere at 1000 particles per cell");
  expectParses(scene(largestGrid, R"({ "shape": "box", "min": [0.05, 0.05, 0.05], "max": [10.1, 10.1, 10.1],
                                       "material": "snow", "particles_per_cell": 1000, "sampler": "poisson_disk" })"),
               "a 1024³ grid filled by a box at 1000 particles per cell");
  expectBadInput(scene(smallGrid, R"({ "shape": "sphere", "center": [0.5, 0.5, 0.5], "radius": 0.2,
                                     "material": "snow", "particles_per_cell": 1e308 })"),
                 "particles_per_cell: must be in (0, 1000]", "1e308 particles per cell");
}

// Found by hand while writing the fuzzer: /dev/zero has no line break, so reading its first line as a text
// point cloud never ended. Only regular files are read now.
TEST(SceneFuzzRegression, BodyFilesThatAreNotRegularFilesAreBadInput) {
  expectBadInput(scene(smallGrid, pointsBody("/dev/zero")), "is not a regular file", "points from /dev/zero");
  expectBadInput(scene(smallGrid, pointsBody("/dev/null")), "is not a regular file", "points from /dev/null");
  expectBadInput(scene(smallGrid, pointsBody("/")), "is a folder", "points from /");
  expectBadInput(scene(smallGrid, pointsBody(fuzzFolder.string())), "is a folder", "points from a folder");
  expectBadInput(scene(smallGrid, pointsBody("/proc/self/mem")), "bodies[0].path", "points from /proc/self/mem");
  expectBadInput(scene(smallGrid, R"({ "shape": "mesh", "path": "/dev/zero", "material": "snow" })"),
                 "is not a regular file", "a mesh from /dev/zero");
  expectBadInput(scene(smallGrid, R"({ "shape": "mesh", "path": "/", "material": "snow" })"), "is a folder",
                 "a mesh from /");
}

// Found by hand while writing the fuzzer: scaled by 1e200, the cloud's squared spacings overflow to infinity
// and the nearest-neighbour search grew its cells for ever. It now stops once a cell spans the cloud, and a
// point or spacing beyond a double is bad input.
TEST(SceneFuzzRegression, PointCloudsPlacedBeyondADoubleAreBadInput) {
  expectBadInput(scene(smallGrid, pointsBody("points.xyz", R"(, "scale": 1e200)")), "further apart than a double",
                 "points scaled by 1e200");
  expectBadInput(scene(smallGrid, pointsBody("points.xyz", R"(, "scale": 1e308, "rotate_deg": [45, 0, 0])")),
                 "further apart than a double", "points scaled by 1e308 and rotated");
  // 1.79e308 + 2e306 is beyond the largest double, 1.797e308.
  expectBadInput(scene(smallGrid, pointsBody("points.xyz", R"(, "scale": 1e308, "translate": [1.79e308, 0, 0])")),
                 "beyond the range of a double", "points scaled by 1e308 and moved by 1.79e308");

  // A grid roomy enough for such a cloud is refused itself: cells are at most 1 km.
  expectBadInput(scene(R"({ "origin": [-1e101, -1e101, -1e101], "cells": [16, 16, 16], "cell_size": 1e100 })",
                       pointsBody("points.xyz", R"(, "scale": 1e100)")),
                 "must be in (0, 1000]", "a grid of 1e100 m cells");
}

TEST(SceneFuzzRegression, NeighbourSpacingBeyondADoubleIsInfiniteAndFound) {
  const double infinity = std::numeric_limits<double>::infinity();
  // Squared distances overflow: the search widens its cells until one spans the cloud, then stops.
  EXPECT_EQ(medianNeighbourSpacingM({glm::dvec3(0.0), glm::dvec3(1e200, 0, 0), glm::dvec3(0, 1e200, 0)}), infinity);
  // The extent itself overflows.
  EXPECT_EQ(medianNeighbourSpacingM({glm::dvec3(-1e308), glm::dvec3(1e308)}), infinity);
  // Just within range the answer is exact.
  EXPECT_EQ(medianNeighbourSpacingM({glm::dvec3(0.0), glm::dvec3(1e150, 0, 0)}), 1e150);
}

}  // namespace
}  // namespace firn

// Bad input at scale (docs/command-line.md, Exit status; docs/scene-format.md, Sizes and limits): input that is
// well-formed but too big is refused before anything is sampled, a mesh file that breaks the importer ends as exit
// 2 naming the file, and bodies that start inside colliders are moved out as pre-flight says. Each command runs
// under a memory limit and a timeout, so a regression fails the test instead of taking the machine down.
#include <sys/resource.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "Cli.h"
#include "Error.h"
#include "GlTest.h"
#include "run/Preflight.h"
#include "scene/Sampling.h"
#include "scene/Scene.h"
#include "sim/Simulation.h"

namespace {

namespace fs = std::filesystem;
using firn::test::freshDirectory;
using firn::test::Result;
using firn::test::runFirn;
using firn::test::writeScene;
using Clock = std::chrono::steady_clock;

// Every command runs with 4 GiB of address space (llvmpipe's threads reserve a few hundred MiB of it) and is
// killed after 60 s: a refusal takes well under a second of its own, and the 60 s leave room for a loaded machine.
// A kill shows as exit 137, which no test accepts.
const std::string kBounded = "ulimit -v 4194304; timeout -s KILL 60";

struct TimedResult {
  Result result;
  double wallS;
};

TimedResult runBounded(const std::string& arguments) {
  const auto start = Clock::now();
  Result result = runFirn(arguments, kBounded);
  return {result, std::chrono::duration<double>(Clock::now() - start).count()};
}

// The largest resident set of any command this test process has waited for (ctest runs each test in a process of
// its own), in bytes.
double peakChildResidentBytes() {
  rusage usage{};
  getrusage(RUSAGE_CHILDREN, &usage);
  return double(usage.ru_maxrss) * 1024;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// 12345 as the messages write it: "12,345".
std::string withThousands(std::size_t value) {
  std::string digits = std::to_string(value);
  for (int i = int(digits.size()) - 3; i > 0; i -= 3) digits.insert(std::size_t(i), ",");
  return digits;
}

// ----- Estimates before sampling -----

// The issue's scene: a box at 64 particles per cell filling a 128³ grid, 97 million particles that once sampled
// for 116 s to 10.9 GB before being refused. The estimate refuses it before sampling: the whole command takes
// seconds (EGL's start on llvmpipe included) and stays under 1 GiB resident, a hundredth of what sampling would
// have taken.
TEST(BadInput, TooManyParticlesAreRefusedBeforeSampling) {
  const fs::path folder = freshDirectory("budget");
  const fs::path scene = writeScene(folder, "dense.json", R"({
    "grid": { "cells": [128, 128, 128], "cell_size": 0.01 },
    "time": { "dt": 1e-4, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.05, 0.05, 0.05], "max": [1.2, 1.2, 1.2], "material": "snow",
                  "particles_per_cell": 64 } ] })");
  const TimedResult run = runBounded("run " + scene.string() + " --out " + (folder / "out").string());
  EXPECT_EQ(run.result.exitCode, 2) << run.result.output;
  // 1.15³ m³ / 0.01³ m³ × 64 = 97,336,000 on the lattice: the estimate names it to the particle.
  EXPECT_TRUE(contains(run.result.output, scene.string() + ": bodies: about 97,336,000 particles")) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "bodies[0], a box at 64 particles per cell")) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "particles_per_cell")) << run.result.output;  // what to change
  EXPECT_LT(run.wallS, 30.0);
  EXPECT_LT(peakChildResidentBytes(), double(1 << 30));
  EXPECT_FALSE(fs::exists(folder / "out" / "frame_0001.ply"));
}

// The README's bunny without --scale 0.1 is 10 m tall: about 194 million particles at 1 cm, refused before sampling
// (it once sampled silently for over 11 minutes) with the estimate and a spacing that fits the default limit.
TEST(BadInput, VoxelizeRefusesAboveMaxParticles) {
  const fs::path folder = freshDirectory("voxelize_budget");
  const fs::path bunny = fs::path(FIRN_SOURCE_DIR) / "assets/meshes/bunny.obj";
  const TimedResult run =
      runBounded("voxelize " + bunny.string() + " --spacing 0.01 --out " + (folder / "bunny.ply").string());
  EXPECT_EQ(run.result.exitCode, 2) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, bunny.string() + ": about ")) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "more than --max-particles 20,000,000")) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "or raise --max-particles")) << run.result.output;
  EXPECT_LT(run.wallS, 30.0);
  EXPECT_LT(peakChildResidentBytes(), double(1 << 30));
  EXPECT_FALSE(fs::exists(folder / "bunny.ply"));

  // The limit is the user's to raise or lower: 1,000 particles refuse what the default lets through.
  const TimedResult small = runBounded("voxelize " + bunny.string() + " --scale 0.1 --spacing 0.01 --max-particles 1000 --out " +
                                       (folder / "small.ply").string());
  EXPECT_EQ(small.result.exitCode, 2) << small.result.output;
  EXPECT_TRUE(contains(small.result.output, "more than --max-particles 1,000")) << small.result.output;
}

// ----- Broken mesh files: a generated corpus in every format the importer is asked to read -----

struct Triangles {
  std::vector<std::string> vertices;  // "x y z", as the text formats write them (so "nan" and "1e39" can appear)
  std::vector<std::array<unsigned, 3>> faces;
};

// The unit cube, outward faces (counter-clockwise seen from outside).
Triangles cube() {
  Triangles mesh;
  mesh.vertices = {"0 0 0", "1 0 0", "1 1 0", "0 1 0", "0 0 1", "1 0 1", "1 1 1", "0 1 1"};
  mesh.faces = {{0, 2, 1}, {0, 3, 2}, {4, 5, 6}, {4, 6, 7}, {0, 1, 5}, {0, 5, 4},
                {3, 6, 2}, {3, 7, 6}, {0, 4, 7}, {0, 7, 3}, {1, 2, 6}, {1, 6, 5}};
  return mesh;
}

std::vector<float> parseVertex(const std::string& text) {
  std::vector<float> xyz(3);
  std::sscanf(text.c_str(), "%f %f %f", &xyz[0], &xyz[1], &xyz[2]);  // "nan", "inf" and 1e39 (→ inf) as floats
  return xyz;
}

template <typename T>
void append(std::string& bytes, T value) {
  bytes.append(reinterpret_cast<const char*>(&value), sizeof value);
}

std::string base64(const std::string& bytes) {
  static const char* digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    std::uint32_t group = std::uint32_t(std::uint8_t(bytes[i])) << 16;
    if (i + 1 < bytes.size()) group |= std::uint32_t(std::uint8_t(bytes[i + 1])) << 8;
    if (i + 2 < bytes.size()) group |= std::uint32_t(std::uint8_t(bytes[i + 2]));
    out += digits[(group >> 18) & 63];
    out += digits[(group >> 12) & 63];
    out += i + 1 < bytes.size() ? digits[(group >> 6) & 63] : '=';
    out += i + 2 < bytes.size() ? digits[group & 63] : '=';
  }
  return out;
}

// A format's file for `mesh`, with `countScale` times the vertex (or triangle) count its header declares.
using Writer = std::function<std::string(const Triangles& mesh, std::uint64_t declaredCount)>;

std::string obj(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string text;
  for (const std::string& v : mesh.vertices) text += "v " + v + "\n";
  // OBJ declares no counts: an index far past the vertices stands for one.
  const bool inflated = declaredCount != mesh.vertices.size();
  for (const auto& f : mesh.faces) {
    text += "f " + std::to_string(f[0] + 1) + " " + std::to_string(f[1] + 1) + " " +
            std::to_string(inflated ? declaredCount : f[2] + 1) + "\n";
  }
  return text;
}

std::string off(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string text = "OFF\n" + std::to_string(declaredCount) + " " + std::to_string(mesh.faces.size()) + " 0\n";
  for (const std::string& v : mesh.vertices) text += v + "\n";
  for (const auto& f : mesh.faces) {
    text += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  }
  return text;
}

std::string plyHeader(const std::string& format, std::uint64_t vertices, std::size_t faces) {
  return "ply\nformat " + format + " 1.0\nelement vertex " + std::to_string(vertices) +
         "\nproperty float x\nproperty float y\nproperty float z\nelement face " + std::to_string(faces) +
         "\nproperty list uchar int vertex_indices\nend_header\n";
}

std::string plyAscii(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string text = plyHeader("ascii", declaredCount, mesh.faces.size());
  for (const std::string& v : mesh.vertices) text += v + "\n";
  for (const auto& f : mesh.faces) {
    text += "3 " + std::to_string(f[0]) + " " + std::to_string(f[1]) + " " + std::to_string(f[2]) + "\n";
  }
  return text;
}

std::string plyBinary(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string bytes = plyHeader("binary_little_endian", declaredCount, mesh.faces.size());
  for (const std::string& v : mesh.vertices) {
    for (float c : parseVertex(v)) append(bytes, c);
  }
  for (const auto& f : mesh.faces) {
    append(bytes, std::uint8_t(3));
    for (unsigned i : f) append(bytes, std::int32_t(i));
  }
  return bytes;
}

std::string stlAscii(const Triangles& mesh, std::uint64_t) {
  std::string text = "solid corpus\n";
  for (const auto& f : mesh.faces) {
    text += "facet normal 0 0 0\nouter loop\n";
    for (unsigned i : f) text += "vertex " + mesh.vertices[i] + "\n";
    text += "endloop\nendfacet\n";
  }
  return text + "endsolid corpus\n";
}

std::string stlBinary(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string bytes(80, ' ');
  // Binary STL declares its triangles: the count scaled as the vertices' elsewhere.
  append(bytes, std::uint32_t(std::min<std::uint64_t>(declaredCount * mesh.faces.size() / mesh.vertices.size(),
                                                      std::numeric_limits<std::uint32_t>::max())));
  for (const auto& f : mesh.faces) {
    for (int c = 0; c < 3; ++c) append(bytes, 0.0f);  // the normal, which importers recompute
    for (unsigned i : f) {
      for (float c : parseVertex(mesh.vertices[i])) append(bytes, c);
    }
    append(bytes, std::uint16_t(0));
  }
  return bytes;
}

std::string gltf(const Triangles& mesh, std::uint64_t declaredCount) {
  std::string buffer;
  for (const std::string& v : mesh.vertices) {
    for (float c : parseVertex(v)) append(buffer, c);
  }
  const std::size_t positionBytes = buffer.size();
  for (const auto& f : mesh.faces) {
    for (unsigned i : f) append(buffer, std::uint32_t(i));
  }
  const std::string n = std::to_string(declaredCount);
  return R"({ "asset": { "version": "2.0" }, "scene": 0, "scenes": [ { "nodes": [0] } ], "nodes": [ { "mesh": 0 } ],
  "meshes": [ { "primitives": [ { "attributes": { "POSITION": 0 }, "indices": 1 } ] } ],
  "buffers": [ { "byteLength": )" + std::to_string(buffer.size()) + R"(, "uri": "data:application/octet-stream;base64,)" +
         base64(buffer) + R"(" } ],
  "bufferViews": [ { "buffer": 0, "byteOffset": 0, "byteLength": )" + std::to_string(positionBytes) + R"( },
                   { "buffer": 0, "byteOffset": )" + std::to_string(positionBytes) + R"(, "byteLength": )" +
         std::to_string(buffer.size() - positionBytes) + R"( } ],
  "accessors": [ { "bufferView": 0, "componentType": 5126, "count": )" + n + R"(, "type": "VEC3",
                   "min": [0, 0, 0], "max": [1, 1, 1] },
                 { "bufferView": 1, "componentType": 5125, "count": )" + std::to_string(3 * mesh.faces.size()) +
         R"(, "type": "SCALAR" } ] })";
}

struct Format {
  std::string extension;
  Writer write;
};

const std::vector<Format>& formats() {
  static const std::vector<Format> all = {{"obj", obj},         {"off", off},           {"ply", plyAscii},
                                          {"b.ply", plyBinary}, {"stl", stlAscii},      {"b.stl", stlBinary},
                                          {"gltf", gltf}};
  return all;
}

// What a corpus file must end in: exactly 0, exactly 2, or either (never a signal, never a hang).
enum class Expect { Ok, BadInput, OkOrBadInput };

struct Variant {
  std::string name;
  Expect expect;
  std::string mustSay;  // a part of the message, with an exit 2
  std::function<std::string(const Format&)> make;
};

std::vector<Variant> variants() {
  const Triangles whole = cube();
  Triangles insideOut = whole;
  for (auto& f : insideOut.faces) std::swap(f[1], f[2]);
  Triangles withNan = whole, withInf = whole, overflowing = whole;
  withNan.vertices[6] = "nan 1 1";
  withInf.vertices[6] = "1 inf 1";
  overflowing.vertices[6] = "1 1 1e39";  // beyond a float's range: infinite once read
  Triangles flat;
  flat.vertices = {"0 0 0", "1 0 0", "1 1 0", "0 1 0"};
  flat.faces = {{0, 1, 2}, {0, 2, 3}};
  const auto same = [](const Triangles& mesh) {
    return [mesh](const Format& format) { return format.write(mesh, mesh.vertices.size()); };
  };
  return {
      {"whole", Expect::Ok, "", same(whole)},
      // The winding number fills flipped meshes as they are (docs/scene-format.md, Sampling).
      {"inside_out", Expect::Ok, "", same(insideOut)},
      // The message shows the vertex as the file has it.
      {"nan", Expect::BadInput, "not finite (the first: (nan, 1, 1))", same(withNan)},
      {"inf", Expect::BadInput, "not finite (the first: (1, inf, 1))", same(withInf)},
      {"overflowing", Expect::BadInput, "not finite (the first: (1, 1, inf))", same(overflowing)},
      {"flat", Expect::BadInput, "flat", same(flat)},
      {"empty", Expect::BadInput, "", [](const Format&) { return std::string(); }},
      // Half the file: what the importer makes of it is its own affair, but it must end in 0 or 2.
      {"truncated", Expect::OkOrBadInput, "",
       [whole](const Format& format) {
         const std::string full = format.write(whole, whole.vertices.size());
         return full.substr(0, full.size() / 2);
       }},
      // Two billion vertices declared for eight: the count the OFF importer once believed, to 15.8 GB and an abort.
      {"inflated", Expect::OkOrBadInput, "",
       [whole](const Format& format) { return format.write(whole, 2000000000); }},
  };
}

TEST(BadInput, BrokenMeshCorpusEndsInZeroOrTwo) {
  const fs::path folder = freshDirectory("mesh_corpus");
  double slowestS = 0;
  for (const Variant& variant : variants()) {
    for (const Format& format : formats()) {
      const fs::path mesh = folder / (variant.name + "." + format.extension);
      std::ofstream(mesh, std::ios::binary) << variant.make(format);
      const TimedResult run =
          runBounded("voxelize " + mesh.string() + " --spacing 0.1 --out " + (folder / "out.ply").string());
      slowestS = std::max(slowestS, run.wallS);
      const int code = run.result.exitCode;
      SCOPED_TRACE(mesh.filename().string() + ": exit " + std::to_string(code) + ": " + run.result.output);
      EXPECT_TRUE(code == 0 || code == 2);
      if (variant.expect == Expect::Ok) {
        EXPECT_EQ(code, 0);
      } else if (variant.expect == Expect::BadInput) {
        EXPECT_EQ(code, 2);
      }
      if (code == 2) {
        EXPECT_TRUE(contains(run.result.output, mesh.string()));  // every refusal names the file
        if (!variant.mustSay.empty()) {
          EXPECT_TRUE(contains(run.result.output, variant.mustSay));
        }
      }
      fs::remove(folder / "out.ply");
    }
  }
  // Each file's answer, the importer's child process and its limits included, in seconds.
  EXPECT_LT(slowestS, 30.0);
}

// The OFF file that once made the importer allocate 15.8 GB and abort, as a mesh body of a scene: `firn run`
// answers exit 2 naming the scene's key and the file, within the importer's limits.
TEST(BadInput, MeshBodyThatBreaksTheImporterIsBadInput) {
  const fs::path folder = freshDirectory("importer_failure");
  std::ofstream(folder / "inflated.off") << off(cube(), 2000000000);
  const fs::path scene = writeScene(folder, "scene.json", R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.1 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "mesh", "path": "inflated.off", "translate": [1, 1, 1], "material": "snow" } ] })");
  const TimedResult run = runBounded("run " + scene.string() + " --out " + (folder / "out").string());
  EXPECT_EQ(run.result.exitCode, 2) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "bodies[0].path")) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, (folder / "inflated.off").string())) << run.result.output;
  EXPECT_LT(run.wallS, 30.0);
}

// ----- Emitters -----

// duration_frames 0 is defined: an emitter's particles all join at its start frame (docs/scene-format.md,
// Emitters), and pre-flight says so.
TEST(BadInput, EmitterOfZeroDurationJoinsAtOnce) {
  const fs::path folder = freshDirectory("emitter_zero");
  const fs::path scene = writeScene(folder, "emitter.json", R"({
    "grid": { "cells": [16, 16, 16], "cell_size": 0.05 },
    "time": { "dt": 1e-3, "frame_rate": 50, "frames": 3 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.3, 0.3, 0.3], "max": [0.5, 0.5, 0.5], "material": "snow" },
                { "shape": "sphere", "center": [0.4, 0.6, 0.4], "radius": 0.06, "material": "snow",
                  "start_frame": 2, "duration_frames": 0 } ] })");
  const TimedResult run = runBounded("run " + scene.string() + " --out " + (folder / "out").string());
  ASSERT_EQ(run.result.exitCode, 0) << run.result.output;
  EXPECT_TRUE(contains(run.result.output, "join at once at frame 2 (duration_frames 0)")) << run.result.output;
}

// ----- Bodies that start inside colliders -----

// A sphere of snow whose lower part lies below a ground plane (as the thesis bunny's 7,505 particles once did and
// stayed for 0.55 s): pre-flight says how many particles start inside and that they are moved out before the first
// step, and they are: none is below the plane as uploaded, nor after 100 steps of falling onto it.
TEST(BadInput, BodiesInsideCollidersAreMovedOutAsPreflightSays) {
  const firn::Scene scene = firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 5e-4, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "sphere", "center": [0.6, 0.35, 0.6], "radius": 0.2, "material": "snow",
                  "particles_per_cell": 8 } ],
    "colliders": [ { "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0], "boundary": "slip" } ] })",
                                             "sphere_in_ground.json");
  const std::vector<firn::ParticleSeed> seeds = firn::sampleBodies(scene);
  std::size_t below = 0;
  for (const firn::ParticleSeed& seed : seeds) below += seed.positionM.y < 0.3f ? 1 : 0;
  // The cap below the plane, 0.15 m of the sphere's 0.4 m, holds π · 0.15² · (3 · 0.2 − 0.15) / 3 = 0.0106 m³ of its
  // 0.0335 m³: about 32% of its particles.
  ASSERT_GT(below, seeds.size() / 4);
  ASSERT_LT(below, seeds.size() * 2 / 5);

  const firn::PreflightReport report = firn::preflight(scene, seeds);
  const std::string expected = "bodies[0]: " + withThousands(below) + " of its " + withThousands(seeds.size()) +
                               " particles start inside colliders[0] (a plane)";
  bool said = false;
  for (const std::string& warning : report.warnings) {
    said = said || (contains(warning, expected) && contains(warning, "moved out to its surface before the first step"));
  }
  EXPECT_TRUE(said) << "no pre-flight warning says: " << expected << "… moved out";

  firn::Simulation simulation(scene, seeds, firn::test::glContext().info());
  const auto lowest = [&] {
    const firn::ParticleSnapshot snapshot = simulation.snapshot();
    float minY = std::numeric_limits<float>::max();
    for (std::size_t i = 0; i < snapshot.size(); ++i) minY = std::min(minY, snapshot.positionMass[i].y);
    return minY;
  };
  // Moved to just outside: the plane at 0.3 m, plus a thousandth of a cell, less a float's rounding there.
  EXPECT_GE(lowest(), 0.3f);
  simulation.advanceTo(100 * scene.time.dtS);
  // The grid stops motion into the plane at its nodes; what interpolation lets a particle past it in 100 steps of
  // 0.5 ms, falling at under 0.5 m/s, is a small part of a cell (0.05 m): a tenth of one bounds it, where the
  // particles left inside would have been up to 0.15 m (3 cells) below.
  EXPECT_GE(lowest(), 0.3f - 0.005f);
}

// A body wholly inside a collider would become a sheet on its surface when moved out: it is refused, naming the
// scene file and the body.
TEST(BadInput, BodyWhollyInsideAColliderIsRefused) {
  const firn::Scene scene = firn::parseScene(R"({
    "grid": { "cells": [24, 24, 24], "cell_size": 0.05 },
    "time": { "dt": 5e-4, "frame_rate": 50, "frames": 1 },
    "materials": { "snow": { "preset": "stomakhin" } },
    "bodies": [ { "shape": "box", "min": [0.5, 0.2, 0.5], "max": [0.7, 0.25, 0.7], "material": "snow" } ],
    "colliders": [ { "type": "plane", "point": [0, 0.3, 0], "normal": [0, 1, 0] } ] })",
                                             "buried.json");
  try {
    firn::preflight(scene, firn::sampleBodies(scene));
    FAIL() << "a buried body was accepted";
  } catch (const firn::InputError& error) {
    EXPECT_TRUE(contains(error.what(), "buried.json: bodies[0]")) << error.what();
    EXPECT_TRUE(contains(error.what(), "starts inside a collider")) << error.what();
  }
}

}  // namespace

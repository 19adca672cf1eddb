// libFuzzer target for the scene parser (docs/scene-format.md). The contract it checks: any text either
// parses into a Scene or throws InputError (bad input, exit status 2). Anything else is a defect: another
// exception type, a crash, a sanitizer report, a hang (-timeout) or a huge allocation (-rss_limit_mb). Only
// InputError is caught; any other exception leaves this function, and std::terminate's abort (after it prints
// the exception's type and what()) is reported by libFuzzer as a crash, with the input saved.
#include <cstddef>
#include <cstdint>
#include <string>

#include "Error.h"
#include "scene/Scene.h"

// Mesh and points bodies name files relative to the scene's folder. Fuzzed scenes are parsed as if they lay in
// tests/fuzz/files/, which holds only a small mesh and two point clouds that the seeds name: a relative path
// finds those or nothing, never a user's files, and the working directory (where libFuzzer's relative corpus
// and artifact paths point) does not matter. Absolute paths (/dev/zero, /proc/self/mem, a folder) still reach
// the loaders, which must refuse them as bad input. Nothing here writes files.
extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    firn::parseScene(text, FIRN_FUZZ_SCENE_FOLDER "/fuzz.json");
  } catch (const firn::InputError&) {
    // Bad input, reported as the contract says.
  }
  return 0;
}

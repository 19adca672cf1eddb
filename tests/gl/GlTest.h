#pragma once
// One headless GL context shared by every test in the GL test binary (llvmpipe in CI).
#include "gl/Context.h"

namespace firn::test {

inline gl::HeadlessContext& glContext() {
  static gl::HeadlessContext context;
  return context;
}

}  // namespace firn::test

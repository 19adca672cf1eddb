// The GL tests' main: gtest's, but the process ends with std::_Exit once the results are written. Zink over lavapipe
// (Mesa 22.3) keeps compiling optimised pipelines on a driver thread after the last test, and neither glFinish nor
// eglTerminate waits for it; exiting through the static destructors frees LLVM's state under that thread, which
// then crashes (SIGSEGV or "corrupted size vs. prev_size") after every test has passed. Ending without the
// destructors leaves nothing for the thread to trip on; the tests' own objects are all destroyed before this.
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  const int status = RUN_ALL_TESTS();
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(status);
}

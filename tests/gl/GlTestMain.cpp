// The GL tests' main: gtest's, but the process ends with std::_Exit once the results are written. Zink over lavapipe
// (Mesa 22.3) keeps compiling optimised pipelines on a driver thread after the last test, and neither glFinish nor
// eglTerminate waits for it; exiting through the static destructors frees LLVM's state under that thread, which
// then crashes (SIGSEGV or "corrupted size vs. prev_size") after every test has passed. Ending without the
// destructors leaves nothing for the thread to trip on; the tests' own objects are all destroyed before this.
//
// A test process that dies of a signal (a driver's thread, or our own fault) says which test was running, on which
// thread, and the stack it died on, so that a crash seen once in CI can be traced: ctest alone reports only
// "SegFault" after the test's "[ RUN ]" line.
#include <gtest/gtest.h>

#include <execinfo.h>
#include <sys/syscall.h>
#include <unistd.h>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace {

// Written when a test starts and ends, read by the signal handler, which must not allocate.
char runningTest[512] = "none (between tests)";

class RunningTestName : public testing::EmptyTestEventListener {
  void OnTestStart(const testing::TestInfo& test) override {
    std::snprintf(runningTest, sizeof runningTest, "%s.%s", test.test_suite_name(), test.name());
  }
  void OnTestEnd(const testing::TestInfo&) override {
    std::snprintf(runningTest, sizeof runningTest, "none (between tests)");
  }
};

void writeText(const char* text) {
  const ssize_t ignored = write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

void writeNumber(unsigned long value) {
  char digits[24];
  int at = int(sizeof digits) - 1;
  digits[at] = '\0';
  do {
    digits[--at] = char('0' + value % 10);
    value /= 10;
  } while (value != 0);
  writeText(digits + at);
}

void reportFatalSignal(int signal) {
  writeText("\nfirn_gl_tests: fatal signal ");
  writeNumber(static_cast<unsigned long>(signal));
  writeText(" (SIG");
  writeText(sigabbrev_np(signal));  // a static table, unlike strsignal's translated text
  writeText(") during ");
  writeText(runningTest);
  const pid_t thread = pid_t(syscall(SYS_gettid));
  writeText(", on thread ");
  writeNumber(static_cast<unsigned long>(thread));
  writeText(thread == getpid() ? " (the main thread)" : " (not the main thread)");
  writeText("; its stack:\n");
  void* frames[64];
  backtrace_symbols_fd(frames, backtrace(frames, 64), STDERR_FILENO);
  // SA_RESETHAND restored the default action: the process ends with the signal, as ctest expects.
  std::raise(signal);
}

void reportFatalSignals() {
  // backtrace loads libgcc's unwinder on its first call, which allocates: do that here, not in the handler.
  void* warmUp[1];
  backtrace(warmUp, 1);
  struct sigaction action {};
  action.sa_handler = reportFatalSignal;
  action.sa_flags = SA_RESETHAND;
  sigemptyset(&action.sa_mask);
  for (const int signal : {SIGSEGV, SIGBUS, SIGILL, SIGFPE, SIGABRT}) sigaction(signal, &action, nullptr);
}

}  // namespace

int main(int argc, char** argv) {
  testing::InitGoogleTest(&argc, argv);
  testing::UnitTest::GetInstance()->listeners().Append(new RunningTestName);
  reportFatalSignals();
  const int status = RUN_ALL_TESTS();
  std::fflush(stdout);
  std::fflush(stderr);
  std::_Exit(status);
}

#pragma once
// KHR_debug hookup and per-pass checks. Release builds do neither: they never synchronise per pass.

namespace firn::gl {

// Debug builds: route the driver's KHR_debug messages to stderr; errors throw GLError from checkPass().
void enableDebugOutput();

// Debug builds: wait for the GPU and throw GLError naming `passName` if GL reported an error.
// Release builds: nothing.
void checkPass(const char* passName);

}  // namespace firn::gl

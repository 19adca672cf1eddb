// What this process may allocate (voxelizer/ProcessMemory.h): the budget before sampling and the importer's memory
// limit rest on it.
#include <cstdint>
#include <string>

#include <gtest/gtest.h>

#include "voxelizer/ChildProcess.h"
#include "voxelizer/ProcessMemory.h"

namespace firn::voxelizer {
namespace {

TEST(ProcessMemory, AllocatableBytesHonoursTheAddressSpaceLimit) {
  // In the child the address space is limited to what it inherited plus 256 MiB: what it may allocate is less.
  ChildLimits limits;
  limits.memoryBytes = std::uint64_t{256} << 20;
  limits.cpuS = 10;
  limits.wallS = 10;
  const ChildOutcome outcome = runInChildProcess([] { return std::to_string(allocatableBytes()); }, limits);
  ASSERT_TRUE(outcome.succeeded) << outcome.failure;
  EXPECT_LT(std::stoull(outcome.result), limits.memoryBytes);
}

}  // namespace
}  // namespace firn::voxelizer

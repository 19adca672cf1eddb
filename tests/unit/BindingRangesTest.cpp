// The checks that keep the GPU contract's binding points apart (gpu/GpuLayout.h): the build runs them on Firn's own
// ranges as static_asserts; here they are shown to reject each kind of collision, so that those asserts can fail.
#include <gtest/gtest.h>

#include "gpu/GpuLayout.h"

using firn::gpu::BindingRange;
using firn::gpu::bindingsWithin;
using firn::gpu::rangesInOrder;

TEST(BindingRanges, FirnsRangesAreInOrderWithinTheRequiredBindings) {
  EXPECT_TRUE(rangesInOrder(firn::gpu::kBindingRanges, FIRN_REQUIRED_STORAGE_BINDINGS));
  // The last range ends exactly at the 32 bindings Firn requires: one more buffer needs a binding given back.
  EXPECT_EQ(FIRN_SURFACE_BINDINGS_END, FIRN_REQUIRED_STORAGE_BINDINGS);
}

TEST(BindingRanges, OverlappingRangesAreRejected) {
  constexpr BindingRange overlapping[] = {{0, 6}, {5, 9}};
  EXPECT_FALSE(rangesInOrder(overlapping, 32));
  constexpr BindingRange adjacent[] = {{0, 6}, {6, 9}};
  EXPECT_TRUE(rangesInOrder(adjacent, 32));
}

TEST(BindingRanges, ARangePastTheLimitIsRejected) {
  constexpr BindingRange ranges[] = {{0, 6}, {6, 33}};
  EXPECT_FALSE(rangesInOrder(ranges, 32));
  EXPECT_TRUE(rangesInOrder(ranges, 33));
}

TEST(BindingRanges, ARepeatedOrStrayBindingIsRejected) {
  // The collision this check was written for: the solver's preconditioner and the surface's header both at 20.
  constexpr int repeated[] = {17, 18, 19, 20, 20};
  EXPECT_FALSE(bindingsWithin(repeated, BindingRange{17, 21}));
  constexpr int stray[] = {17, 18, 21};
  EXPECT_FALSE(bindingsWithin(stray, BindingRange{17, 21}));
  constexpr int distinct[] = {20, 17, 19, 18};
  EXPECT_TRUE(bindingsWithin(distinct, BindingRange{17, 21}));
}

// 64-bit integers as a low (unsigned) and a high (signed) 32-bit word, for the sums that must be exact and whose
// values need more than 32 bits (docs/numerics.md, The semi-implicit solve). GLSL 4.30 has no 64-bit integers, and
// llvmpipe no 64-bit atomics: a sum is two words, with the carry taken by hand.

const float TWO_TO_32 = 4294967296.0;
// Largest magnitude a single contribution may have: 2^62. A node's sum of many stays within 64 bits because the
// host picks the solve's fraction bits k_H so that the largest node sum it bounds stays below 2^62
// (sim/FixedPoint.cpp, deriveSolverFractionBits).
const float FIXED64_LIMIT = 4611686018427387904.0;

// x as (low, high): x is an integer-valued float below 2^62 in magnitude. Its magnitude splits exactly (|x| mod
// 2^32 is a multiple of |x|'s last place, and so a float), and a negative x is then negated in integers: a
// float split of x itself would round, as 2^32 − |x| needs 32 bits where a float has 24.
void splitFixed64(vec4 x, out uvec4 low, out ivec4 high) {
  vec4 magnitude = abs(x);
  vec4 highPart = floor(magnitude * (1.0 / TWO_TO_32));
  uvec4 magnitudeLow = uvec4(magnitude - highPart * TWO_TO_32);
  uvec4 magnitudeHigh = uvec4(highPart);
  uvec4 carry;
  uvec4 negatedLow = uaddCarry(~magnitudeLow, uvec4(1u), carry);
  // All ones where x is negative (GLSL 4.30's mix takes no integer vectors).
  uvec4 negative = uvec4(lessThan(x, vec4(0.0))) * 0xffffffffu;
  low = (negatedLow & negative) | (magnitudeLow & ~negative);
  high = ivec4(((~magnitudeHigh + carry) & negative) | (magnitudeHigh & ~negative));
}

// (low, high) += (addLow, addHigh).
void addFixed64(inout uvec3 low, inout ivec3 high, uvec3 addLow, ivec3 addHigh) {
  uvec3 carry;
  low = uaddCarry(low, addLow, carry);
  high += addHigh + ivec3(carry);
}
void addFixed64(inout uvec4 low, inout ivec4 high, uvec4 addLow, ivec4 addHigh) {
  uvec4 carry;
  low = uaddCarry(low, addLow, carry);
  high += addHigh + ivec4(carry);
}

// The value of (low, high) as a float: its magnitude is converted, so that a small negative value (high −1, low
// near 2^32) does not cancel to nothing.
float fixed64ToFloat(uint low, int high) {
  bool negative = high < 0;
  uint carry;
  uint magnitudeLow = negative ? uaddCarry(~low, 1u, carry) : low;
  uint magnitudeHigh = negative ? uint(~high) + carry : uint(high);
  float magnitude = float(magnitudeHigh) * TWO_TO_32 + float(magnitudeLow);
  return negative ? -magnitude : magnitude;
}
vec4 fixed64ToFloat(uvec4 low, ivec4 high) {
  return vec4(fixed64ToFloat(low.x, high.x), fixed64ToFloat(low.y, high.y), fixed64ToFloat(low.z, high.z),
              fixed64ToFloat(low.w, high.w));
}

bool nonzero(uvec3 low, ivec3 high) { return any(notEqual(low, uvec3(0u))) || any(notEqual(high, ivec3(0))); }
bool nonzero(uvec4 low, ivec4 high) { return any(notEqual(low, uvec4(0u))) || any(notEqual(high, ivec4(0))); }

// Adds the 64-bit value (low, high) to the words lowWord/highWord, in storage or shared memory: the low word's
// atomicAdd returns the sum before, which tells whether it carried into the high word. The words end as the exact
// 64-bit sum whatever the order of the additions. (Macros: GLSL's atomics take the variable itself.)
#define FIRN_ADD_FIXED64_WORD(lowWord, highWord, low, high)           \
  if ((low) != 0u || (high) != 0) {                                   \
    uint previous = atomicAdd(lowWord, low);                          \
    int carry = previous + (low) < previous ? 1 : 0;                  \
    if ((high) + carry != 0) atomicAdd(highWord, (high) + carry);     \
  }
// Each of the four words of a node's 64-bit sums (lowWords/highWords, uvec4/ivec4), as above.
#define FIRN_ADD_FIXED64(lowWords, highWords, low, high) \
  for (int c = 0; c < 4; ++c) {                          \
    FIRN_ADD_FIXED64_WORD(lowWords[c], highWords[c], low[c], high[c]) \
  }
